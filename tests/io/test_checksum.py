"""Every dataset records a checksum of its values; reading and `sleighsim verify` catch a flipped byte."""

import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from sleighsim import cli
from sleighsim.io.checksum import ATTR, ChecksumError, verify
from sleighsim.io.netcdf import read_dataset, write_dataset

KNOWN = np.arange(1000.0) * np.pi  # bytes that occur once in the file: its data region


def dataset():
    return xr.Dataset({"u": ("time", KNOWN), "status": ("time", ["converged", "undecided"] * 500),
                       "flag": ("time", np.arange(1000) % 3 == 0), "gap": ("time", np.where(KNOWN > 9, -KNOWN, np.nan)),
                       "count": ("time", np.arange(1000, dtype="int8"))},
                      coords={"time": np.arange(1000) * 0.5,
                              "day": ("time", pd.date_range("2026-01-01", periods=1000))},
                      attrs={"scene": "unit"})


def flip(path, needle: bytes, offset: int = 0, mask: int = 0xFF):
    """Flip 8 bytes of ``path`` (the bits of ``mask``) at ``offset`` bytes into the single place
    ``needle`` occurs."""
    raw = bytearray(path.read_bytes())
    at = raw.find(needle)
    assert at >= 0 and raw.find(needle, at + 1) < 0, "the needle should occur once"
    raw[at + offset: at + offset + 8] = bytes(b ^ mask for b in raw[at + offset: at + offset + 8])
    path.write_bytes(bytes(raw))


def test_a_written_dataset_records_a_checksum_that_a_read_checks_and_leaves_out(tmp_path):
    path = write_dataset(dataset(), tmp_path / "a.nc")
    assert verify(path).startswith("sha256:") and len(verify(path)) == 7 + 64
    back = read_dataset(path)
    assert ATTR not in back.attrs and np.array_equal(back.u.values, KNOWN)
    again = write_dataset(back, tmp_path / "b.nc")  # written again from what was read: its own checksum
    assert verify(again) != verify(path)  # the attributes are covered: its history line differs


@pytest.mark.parametrize("needle, offset", [(KNOWN[500:502].tobytes(), 0), (KNOWN[500:502].tobytes(), 3),
                                            ((np.arange(1000) * 0.5)[700:702].tobytes(), 0)],
                         ids=["a variable", "a variable, straddling values", "a coordinate"])
def test_eight_flipped_bytes_in_the_data_are_caught_by_read_and_verify(tmp_path, capsys, needle, offset):
    path = write_dataset(dataset(), tmp_path / "results" / "data" / "bad.nc")
    write_dataset(dataset(), tmp_path / "results" / "data" / "good.nc")
    flip(path, needle, offset)
    with xr.open_dataset(path) as still_opens:  # the file still opens: only its values changed
        assert still_opens.sizes["time"] == 1000
    with pytest.raises(ChecksumError, match=rf"^{path}: its data do not match the checksum recorded"):
        read_dataset(path)
    assert cli.main(["verify", str(tmp_path / "results")]) == 1
    out = capsys.readouterr().out
    assert f"FAILED {path}: its data do not match" in out and "good.nc" not in out
    assert "2 datasets checked" in out and "1 failed" in out


def test_a_changed_text_is_caught(tmp_path):
    path = write_dataset(xr.Dataset({"verdict": ("state", ["regular", "chaotic-but-unique-text"])}), tmp_path / "t.nc")
    flip(path, b"chaotic-but-unique-text", 2, mask=0x01)  # still valid text: "ahcn`sid..."
    with pytest.raises(ChecksumError, match="do not match"):
        read_dataset(path)


def test_a_dataset_without_a_checksum_is_refused_naming_it_unless_unverified(tmp_path):
    path = tmp_path / "foreign.nc"
    dataset().to_netcdf(path)
    with pytest.raises(ChecksumError, match=rf"^{path}: records no checksum \(sleighsim_checksum\)"):
        read_dataset(path)
    assert np.array_equal(read_dataset(path, verified=False).u.values, KNOWN)


def test_verify_passes_a_clean_tree_and_names_an_unreadable_file(tmp_path, capsys):
    write_dataset(dataset(), tmp_path / "data" / "sub" / "a.nc")
    assert cli.main(["verify", str(tmp_path)]) == 0
    assert "1 datasets checked" in capsys.readouterr().out
    (tmp_path / "data" / "half.nc").write_bytes(b"CDF\x01 truncated")
    assert cli.main(["verify", str(tmp_path)]) == 1
    assert f"FAILED {tmp_path / 'data' / 'half.nc'}: cannot be read" in capsys.readouterr().out
    assert cli.main(["verify", str(tmp_path / "absent")]) == 2


def test_every_dataset_read_goes_through_the_checked_reader(root):
    """Only sleighsim.io opens netCDF files (integrity only to see whether one opens at all): every rule
    and library read is read_dataset's, which checks the checksum."""
    io = root / "src" / "sleighsim" / "io"
    allowed = {io / "netcdf.py", io / "checksum.py", io / "integrity.py"}
    sources = [*(root / "src").rglob("*.py"), *(root / "workflow").rglob("*.py"), *(root / "workflow").rglob("*.smk"),
               root / "workflow" / "Snakefile"]
    opening = re.compile(r"open_dataset|open_mfdataset|load_dataset|netCDF4\.Dataset\(|h5py|open_datatree")
    assert [str(p.relative_to(root)) for p in sources if p not in allowed and opening.search(p.read_text())] == []
