"""The decisive stage's one job holds every (realization, state) lane of the stage: its lanes' datasets
(``verdict_decisive.decisive_lanes``, one per lane as a realization's dataset takes them in) packed into
one dataset along ``decisive_lane`` and unpacked again where the realizations are gathered.

Packing keeps each lane exactly: its state name and realization, the lengths of its ragged dimensions
(its spike intervals and the return map's returns, NaN-padded to the longest lane in the pack) and its
attributes (as JSON text, numbers and lists of them)."""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

#: The ragged dimensions of a lane: NaN-padded in the pack, cut back to the lane's own length on unpacking.
RAGGED = ("decisive_spike", "decisive_return")


def _plain(x):
    """A JSON-ready value for a numpy scalar or array in an attribute."""
    return x.tolist() if hasattr(x, "tolist") else str(x)


def pack(parts: list, realizations: list) -> xr.Dataset:
    """One dataset of the lanes ``parts`` (each a one-state decisive dataset) of the realizations
    ``realizations`` (one per part), along ``decisive_lane``; attributes: those of the first lane's stage."""
    if len(parts) != len(realizations) or not parts:
        raise ValueError(f"{len(parts)} lanes for {len(realizations)} realizations")
    width = {d: max(p.sizes.get(d, 0) for p in parts) for d in RAGGED}
    lanes = []
    for p in parts:
        q = p.isel(state=0).reset_coords("state", drop=True)
        lanes.append(q.pad({d: (0, width[d] - p.sizes[d]) for d in RAGGED if d in p.dims}))
    ds = xr.concat(lanes, dim="decisive_lane", data_vars="all", coords="minimal", compat="override",
                   combine_attrs="override")  # the variables' attributes: every lane's are the same
    ds.attrs = {}
    ds["decisive_lane_state"] = ("decisive_lane", np.array([str(p.state.values[0]) for p in parts], dtype=object),
                                 {"long_name": "the state of each lane"})
    ds["decisive_lane_realization"] = ("decisive_lane", np.asarray(realizations, int),
                                       {"long_name": "the realization of each lane", "units": "1"})
    for d in RAGGED:
        ds[f"{d}_count"] = ("decisive_lane", [p.sizes.get(d, 0) for p in parts],
                            {"long_name": f"each lane's own length along {d} (the pack NaN-pads the rest)",
                             "units": "1"})
    ds["decisive_lane_attrs"] = ("decisive_lane", np.array([json.dumps(p.attrs, default=_plain) for p in parts],
                                                           dtype=object),
                                 {"long_name": "each lane's attributes as JSON text"})
    ds.attrs.update(stage="decisive", lanes=len(parts),
                    **{k: v for k, v in parts[0].attrs.items() if k in ("decisive_precision", "decisive_T",
                                                                         "decisive_tangent", "backend")})
    ds.attrs["wall_time_s"] = float(sum(p.attrs["wall_time_s"] for p in parts))
    return ds


def unpack(ds: xr.Dataset) -> list[tuple[int, xr.Dataset]]:
    """The lanes of a pack: (realization, the lane's one-state dataset as ``pack`` took it in)."""
    out = []
    own = ["decisive_lane_state", "decisive_lane_realization", "decisive_lane_attrs", *(f"{d}_count" for d in RAGGED)]
    for i in range(ds.sizes["decisive_lane"]):
        lane = ds.isel(decisive_lane=i)
        cut = {d: slice(0, int(lane[f"{d}_count"])) for d in RAGGED if d in ds.dims}
        part = lane.isel(cut).drop_vars(own).expand_dims(state=[str(lane.decisive_lane_state.values)])
        part.attrs = json.loads(str(lane.decisive_lane_attrs.values))
        out.append((int(lane.decisive_lane_realization), part))
    return out
