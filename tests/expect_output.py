#!/usr/bin/env python3
"""Runs a command and checks both its exit code and its output.

Usage: expect_output.py PATTERN [--nonblank IMAGE]... -- COMMAND [ARG...]

Passes when COMMAND exits with code 0 and its output (standard output and
standard error together) matches the regular expression PATTERN (Python re
with DOTALL, so "." also matches a newline, as in ctest's regular
expressions). ctest's PASS_REGULAR_EXPRESSION alone would pass a command that
prints the text and then fails, because ctest ignores the exit code when that
property is set; tests use this script instead.

--nonblank IMAGE (repeatable): IMAGE is removed before COMMAND runs, and must
then exist and not be blank: some channel takes more than one value
(`oiiotool --stats`), so a constant image, e.g. all background, fails.
"""
import os
import re
import subprocess
import sys


def image_varies(path):
    stats = subprocess.run(["oiiotool", "--stats", path], capture_output=True, text=True)
    if stats.returncode != 0:
        return f"oiiotool cannot read it: {stats.stdout}{stats.stderr}"
    lo = re.search(r"Stats Min: (.*)", stats.stdout)
    hi = re.search(r"Stats Max: (.*)", stats.stdout)
    if not lo or not hi:
        return f"oiiotool printed no statistics: {stats.stdout}"
    lows = [float(v) for v in re.findall(r"-?[0-9.]+(?:e[-+]?[0-9]+)?", lo.group(1))]
    highs = [float(v) for v in re.findall(r"-?[0-9.]+(?:e[-+]?[0-9]+)?", hi.group(1))]
    if not any(h > l for l, h in zip(lows, highs)):
        return f"every channel is constant (min {lo.group(1)}, max {hi.group(1)})"
    return None


def main(argv):
    if "--" not in argv or len(argv) < 3:
        print(__doc__)
        return 2
    sep = argv.index("--")
    pattern, options, command = argv[1], argv[2:sep], argv[sep + 1:]
    images = [options[i + 1] for i in range(0, len(options) - 1, 2) if options[i] == "--nonblank"]
    if len(images) * 2 != len(options):
        print(f"expect_output.py: bad options {options}")
        return 2
    for image in images:
        try:
            os.remove(image)
        except FileNotFoundError:
            pass
    run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    sys.stdout.write(run.stdout)
    failed = False
    if run.returncode != 0:
        print(f"FAIL: exit code {run.returncode}, expected 0")
        failed = True
    if not re.search(pattern, run.stdout, re.DOTALL):
        print(f"FAIL: the output does not match /{pattern}/")
        failed = True
    for image in images:
        problem = image_varies(image)
        if problem:
            print(f"FAIL: {image}: {problem}")
            failed = True
    if not failed:
        print("ok")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
