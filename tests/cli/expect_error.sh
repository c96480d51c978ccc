#!/usr/bin/env bash
# Usage: expect_error.sh PATTERN OUTPUT_FILE -- COMMAND...
# Passes when COMMAND exits non-zero, prints exactly one line on stderr matching
# the extended regex PATTERN, does not crash (exit code < 128) and leaves no
# OUTPUT_FILE (nor a temporary file beside it) behind.
set -u
pattern="$1"; out="$2"; shift 3
rm -f "$out"
err="$(mktemp)"
"$@" >/dev/null 2>"$err" </dev/null
rc=$?
status=0
if [ $rc -eq 0 ]; then echo "FAIL: exit code 0, expected an error"; status=1; fi
if [ $rc -ge 128 ]; then echo "FAIL: crashed (exit code $rc)"; status=1; fi
lines=$(grep -c '' "$err")
if [ "$lines" -ne 1 ]; then echo "FAIL: expected one line on stderr, got $lines:"; cat "$err"; status=1; fi
if ! grep -Eq -- "$pattern" "$err"; then echo "FAIL: stderr does not match /$pattern/:"; cat "$err"; status=1; fi
if [ -e "$out" ]; then echo "FAIL: output file $out was written"; status=1; fi
dir="$(dirname "$out")"
if [ -d "$dir" ] && ls -a "$dir" 2>/dev/null | grep -q '\.tmp[0-9]'; then echo "FAIL: temporary file left in $dir"; status=1; fi
[ $status -eq 0 ] && echo "ok: exit $rc: $(cat "$err")"
rm -f "$err"
exit $status
