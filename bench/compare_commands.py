#!/usr/bin/python3
"""Times one command line run by two or more programs, alternating them in
rounds (so that a busy host slows all of them alike), and prints each one's
median wall time and the ratio of the first median to the second.

  bench/compare_commands.py ROUNDS PROGRAM1,PROGRAM2[,...] ARGS...

OUT in ARGS becomes a per-program output file (/tmp/compare_commands_<i>.png),
so the images can be compared afterwards. Round 0 is a warm-up and not
counted. Example (docs/performance.md, the image module):

  bench/compare_commands.py 10 old/build/debugger/rayscope,build/debugger/rayscope \\
      render -q data/scenes/bunny_glass.json --size 800x600 --spp 1 --threads 2 -o OUT
"""
import statistics
import subprocess
import sys
import time


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rounds = int(sys.argv[1])
    programs = sys.argv[2].split(",")
    args = sys.argv[3:]
    times = {p: [] for p in programs}
    for r in range(rounds + 1):
        for i, p in enumerate(programs):
            cmd = [p] + [a.replace("OUT", "/tmp/compare_commands_%d.png" % i) for a in args]
            t = time.perf_counter()
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            if r:
                times[p].append(time.perf_counter() - t)
    for p in programs:
        print("%-45s median %.3f s  (min %.3f, max %.3f, n=%d)" %
              (p, statistics.median(times[p]), min(times[p]), max(times[p]), len(times[p])))
    if len(programs) > 1:
        print("ratio first/second %.2f" %
              (statistics.median(times[programs[0]]) / statistics.median(times[programs[1]])))


if __name__ == "__main__":
    main()
