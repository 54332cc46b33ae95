"""``python -m harmonav.experiment run SPEC --out DIR [--engine local|ray] [--address ADDR]``
and ``python -m harmonav.experiment report DIR``. Exit codes: 0 success, 2 a bad spec or
folder, 130 interrupted (the parts written are kept; the same command resumes)."""

import argparse
import sys


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m harmonav.experiment",
        description="Run an experiment spec on every local core or on a Ray cluster, with "
        "Parquet records, and report its tables (docs/experiments.md).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a spec; resumes from the parts already in --out")
    r.add_argument("spec", help="the experiment spec (TOML)")
    r.add_argument("--out", required=True, help="the folder of the records")
    r.add_argument("--engine", choices=["local", "ray"], help="default: the spec's [engine] kind")
    r.add_argument("--address", help="ray: the address of a running cluster (ray start --head)")
    r.add_argument("--workers", type=int, help="local threads or local Ray CPUs (0: every core)")
    bar = r.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None,
                     help="show the progress bar even when stderr is not a terminal")
    bar.add_argument("--no-progress", dest="progress", action="store_false")
    p = sub.add_parser("report", help="print the tables of an experiment's records and draw them")
    p.add_argument("out", help="the folder of the records")
    p.add_argument("--plots", help="the folder of the SVG plots (default: OUT/report)")
    p.add_argument("--no-plots", action="store_true", help="print the tables only")
    args = parser.parse_args(argv)
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        print("harmonav.experiment needs pyarrow: pip install './python[experiment]'", file=sys.stderr)
        return 2
    from .spec import SpecError

    try:
        if args.command == "run":
            from .runner import main_run

            return main_run(args)
        from .reporting import main_report

        return main_report(args)
    except SpecError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
