"""`python -m uavdamp.sources.flight_log PATH [--band LOW HIGH] [--window START END]`: what a flight log holds."""

from __future__ import annotations

import argparse
import sys

from uavdamp.sources.flight_log.info import describe
from uavdamp.sources.flight_log.records import FlightLogError


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m uavdamp.sources.flight_log", description=__doc__)
    parser.add_argument("path", help="a PX4 .ulg, ArduPilot .bin or the documented .csv")
    parser.add_argument("--band", nargs=2, type=float, metavar=("LOW_HZ", "HIGH_HZ"), help="PSD peaks in this band")
    parser.add_argument("--window", nargs=2, type=float, metavar=("START_S", "END_S"), help="log time span")
    parser.add_argument("--blades", type=int, default=2, help="per rotor, for rotor-speed lines (default 2)")
    args = parser.parse_args(argv)
    try:
        print(describe(args.path, band_hz=args.band, window_s=args.window, blades=args.blades))
    except (FlightLogError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
