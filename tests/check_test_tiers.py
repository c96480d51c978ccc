#!/usr/bin/env python3
"""Fails unless every ctest test of a build directory has exactly one tier label.

Usage: check_test_tiers.py BUILD_DIR

The tiers (tests/CMakeLists.txt): quick, slow, display, paraview, fuzz. The
list comes from `ctest --show-only=json-v1`, so GoogleTest cases discovered at
build time are included.
"""
import json
import subprocess
import sys

TIERS = ("quick", "slow", "display", "paraview", "fuzz")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = subprocess.run(["ctest", "--test-dir", sys.argv[1], "--show-only=json-v1"],
                         check=True, capture_output=True, text=True).stdout
    tests = json.loads(out)["tests"]
    bad = []
    counts = {t: 0 for t in TIERS}
    for test in tests:
        labels = []
        for prop in test.get("properties", []):
            if prop["name"] == "LABELS":
                labels = prop["value"]
        tiers = [label for label in labels if label in TIERS]
        if len(tiers) != 1:
            bad.append("%s: %s" % (test["name"], ", ".join(tiers) or "no tier label"))
        else:
            counts[tiers[0]] += 1
    print("%d tests: %s" % (len(tests), ", ".join("%d %s" % (counts[t], t) for t in TIERS)))
    if bad:
        print("tests without exactly one tier label (%s):" % ", ".join(TIERS))
        for line in bad:
            print("  " + line)
        sys.exit(1)


if __name__ == "__main__":
    main()
