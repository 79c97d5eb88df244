"""Is the steady state a start state reaches chaotic? The workflow's chaos verdict for one state of one's own
(:func:`sleighsim.ops.judge.judge_state`): progress on stderr, the verdict with its reasons on stdout.

    sleighsim judge --params eps=0.05 b=1 K2=1.1 --state 0 0.1 1 0 --horizon 1e5 --out verdict.nc
    sleighsim judge --state 0 0.1 1 0 --realizations 1 --configfile config/smoke.yaml   # a quick look

Every setting not given is the config's chaos_verdict block's (config/config.yaml, the paper's, with any
--configfile merged onto it): the parameters, the number of realizations, the decisive stage's horizon T
(time units) and arithmetic (double-double).
"""

from __future__ import annotations

import argparse
import logging
import sys

from sleighsim.ops.helptext import summary
from sleighsim.ops.judge import answer, judge_state, write
from sleighsim.precision import Precision


def _pair(text: str) -> tuple[str, float]:
    key, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"{text!r}: give KEY=VALUE (eps=0.05)")
    return key, float(value)


def _parser(prog: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=prog, description=summary(__doc__))
    p.add_argument("--state", type=float, nargs=4, required=True, metavar=("u", "Omega", "omega", "delta"),
                   help="the start state (judged at its own energy label unless --label is given)")
    p.add_argument("--params", type=_pair, nargs="+", metavar="KEY=VALUE",
                   help="the paper form eps= b= K2= or the physical form m_c= m_r= I_c= I_r= a= b= (default: the "
                        "config's chaos_verdict block's)")
    p.add_argument("--horizon", type=float, help="the decisive stage's T, in time units")
    p.add_argument("--precision", choices=[m.value for m in Precision], help="the decisive stage's arithmetic")
    p.add_argument("--realizations", type=int, help="start states perturbed at the rounding level that must agree")
    p.add_argument("--label", type=float, help="scale the state's velocities to this energy label first")
    p.add_argument("--configfile", nargs="+", default=[], help="config overlays merged onto config/config.yaml")
    p.add_argument("--out", help="write the verdict dataset (netCDF) here")
    return p


def main(argv=None, prog: str = "sleighsim judge") -> int:
    """Judge the state and print its verdict; exit 0 (2 on a usage error or a refused input, named)."""
    args = _parser(prog).parse_args(argv)
    log, handler = logging.getLogger("sleighsim"), logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(asctime)s %(message)s", datefmt="%H:%M:%S"))
    level = log.level
    log.addHandler(handler)
    log.setLevel(logging.INFO)  # the progress of the long work, on stderr
    try:
        ds = judge_state(dict(args.params) if args.params else None, args.state, args.horizon,
                         precision=args.precision, realizations=args.realizations, label=args.label,
                         configfiles=args.configfile)
    except (ValueError, TypeError) as why:
        print(f"{prog}: {why}", file=sys.stderr)
        return 2
    finally:
        log.removeHandler(handler)
        log.setLevel(level)
    if args.out:
        write(ds, args.out)
    a = answer(ds)
    for label, text in (("verdict", f"{a.verdict} (class: {a.klass})"), ("decided in", a.arithmetic),
                        ("decided by", a.decided_by or "no judge"), ("why", a.why), ("to decide it", a.to_decide)):
        if text:
            print(f"{label}: {text}")
    return 0
