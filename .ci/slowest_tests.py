#!/usr/bin/env python3
"""The longest tests of the last ctest run in a build directory, from its LastTest.log (ctest
keeps whole seconds there): where a CI stage's minutes went, so the next cut is measured, not
guessed (README: the suite stays within 45 minutes on 2 cores).

  python3 .ci/slowest_tests.py BUILD_DIR [--top N]
"""
import argparse
import re
import sys
from pathlib import Path


def elapsed(log_text):
    """(seconds, name) of each test run the log records (a retried test once per try)."""
    runs = []
    for match in re.finditer(r'^"(.+)" time elapsed: (\d+):(\d+):(\d+)$', log_text, re.M):
        name, hours, minutes, seconds = match.group(1), *map(int, match.groups()[1:])
        runs.append((hours * 3600 + minutes * 60 + seconds, name))
    return runs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("build_dir")
    parser.add_argument("--top", type=int, default=15)
    args = parser.parse_args()
    log = Path(args.build_dir) / "Testing" / "Temporary" / "LastTest.log"
    if not log.is_file():
        print(f"slowest tests: no {log}", file=sys.stderr)
        return 0  # a report, never a reason to fail the stage
    runs = elapsed(log.read_text(errors="replace"))
    total = sum(seconds for seconds, _ in runs)
    print(f"slowest tests in {args.build_dir} ({len(runs)} runs, {total} test-seconds in all):")
    for seconds, name in sorted(runs, reverse=True)[: args.top]:
        print(f"  {seconds:5d} s  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
