#!/usr/bin/env bash
# Usage: expect_warning.sh PATTERN OUTPUT_FILE -- COMMAND...
# Passes when COMMAND exits 0 (no crash), prints exactly one line on stderr,
# that line matches the extended regex PATTERN, and OUTPUT_FILE was written
# (non-empty, no temporary file left beside it). For input that is bad but
# can be worked around: one clear warning, and the work still gets done.
set -u
pattern="$1"; out="$2"; shift 3
rm -f "$out"
err="$(mktemp)"
"$@" >/dev/null 2>"$err" </dev/null
rc=$?
status=0
if [ $rc -ne 0 ]; then echo "FAIL: exit code $rc, expected 0"; status=1; fi
lines=$(grep -c '' "$err")
if [ "$lines" -ne 1 ]; then echo "FAIL: expected one line on stderr, got $lines:"; cat "$err"; status=1; fi
if ! grep -Eq -- "$pattern" "$err"; then echo "FAIL: stderr does not match /$pattern/:"; cat "$err"; status=1; fi
if [ ! -s "$out" ]; then echo "FAIL: output file $out was not written"; status=1; fi
dir="$(dirname "$out")"
if [ -d "$dir" ] && ls -a "$dir" 2>/dev/null | grep -q '\.tmp[0-9]'; then echo "FAIL: temporary file left in $dir"; status=1; fi
[ $status -eq 0 ] && echo "ok: $(cat "$err")"
rm -f "$err"
exit $status
