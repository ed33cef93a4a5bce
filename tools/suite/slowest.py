#!/usr/bin/env python3
"""Prints the slowest test binaries and tests of a suite run.

    tools/suite/slowest.py TIMES LOG [N]

TIMES is the file tools/suite/runner.sh appended to (binary, wall seconds,
exit status); LOG the output of `cargo test` run with that runner, whose
lines read `test NAME ... ok <12.345s>`. A test's time is its wall time in
a binary whose tests run two at a time and take the GPU in turn, so it
includes waiting for the device; a binary's time is what the suite paid.
"""
import re
import sys


def main():
    times, log = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 15
    bins = []
    for line in open(times):
        name, secs, rc = line.rstrip("\n").split("\t")
        bins.append((float(secs), name, rc))
    bins.sort(reverse=True)
    total = sum(b[0] for b in bins)
    print(f"test binaries: {len(bins)}, {total:.0f} s in all; the slowest:")
    for secs, name, rc in bins[:n]:
        print(f"  {secs:7.1f} s  {name}{'' if rc == '0' else '  (exit ' + rc + ')'}")
    tests = []
    binary = "?"
    for line in open(log, errors="replace"):
        m = re.match(r"\s*Running (\S+)", line)
        if m:
            binary = m.group(1)
        m = re.match(r"test (\S+) \.\.\. (\w+) <([0-9.]+)s>", line)
        if m:
            tests.append((float(m.group(3)), binary, m.group(1), m.group(2)))
    tests.sort(reverse=True)
    print(f"tests: {len(tests)}; the slowest (wall time, waits for the GPU included):")
    for secs, binary, name, result in tests[:n]:
        print(f"  {secs:7.1f} s  {binary} {name}{'' if result == 'ok' else '  ' + result}")


if __name__ == "__main__":
    main()
