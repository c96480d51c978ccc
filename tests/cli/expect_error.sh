#!/usr/bin/env bash
# Usage: expect_error.sh [--warning] PATTERN OUTPUT_FILE -- COMMAND...
# Passes when COMMAND prints exactly one line on stderr matching the extended
# regex PATTERN, does not crash (exit code < 128), and leaves no temporary file
# of OUTPUT_FILE beside it, and
#  - by default (bad input): exits non-zero and leaves no OUTPUT_FILE behind;
#  - with --warning (input that is bad but can be worked around: one clear
#    warning, and the work still gets done): exits 0 and writes a non-empty
#    OUTPUT_FILE.
set -u
warning=0
if [ "${1:-}" = --warning ]; then warning=1; shift; fi
pattern="$1"; out="$2"; shift 3
rm -f "$out"
err="$(mktemp)"
"$@" >/dev/null 2>"$err" </dev/null
rc=$?
status=0
if [ $warning -eq 1 ]; then
  if [ $rc -ne 0 ]; then echo "FAIL: exit code $rc, expected 0"; status=1; fi
  if [ ! -s "$out" ]; then echo "FAIL: output file $out was not written"; status=1; fi
else
  if [ $rc -eq 0 ]; then echo "FAIL: exit code 0, expected an error"; status=1; fi
  if [ $rc -ge 128 ]; then echo "FAIL: crashed (exit code $rc)"; status=1; fi
  if [ -e "$out" ]; then echo "FAIL: output file $out was written"; status=1; fi
fi
lines=$(grep -c '' "$err")
if [ "$lines" -ne 1 ]; then echo "FAIL: expected one line on stderr, got $lines:"; cat "$err"; status=1; fi
if ! grep -Eq -- "$pattern" "$err"; then echo "FAIL: stderr does not match /$pattern/:"; cat "$err"; status=1; fi
# The writer's temporary files are named .STEM.tmpPID_N.EXT (write_atomically
# in raytracer/src/image.cpp). Only this output's own count: other tests write
# into the same folder at the same time.
dir="$(dirname "$out")"
base="$(basename "$out")"
stem="${base%.*}"
ext=""
[ "$stem" != "$base" ] && ext=".${base##*.}"
shopt -s nullglob
leftovers=("$dir"/."$stem".tmp*"$ext")
if [ ${#leftovers[@]} -ne 0 ]; then echo "FAIL: temporary file left: ${leftovers[*]}"; status=1; fi
[ $status -eq 0 ] && echo "ok: exit $rc: $(cat "$err")"
rm -f "$err"
exit $status
