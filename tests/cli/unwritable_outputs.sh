#!/usr/bin/env bash
# Usage: unwritable_outputs.sh RAYSCOPE WORK_DIR
# Outputs that cannot be written are refused before the scene is loaded and
# rendered: each case is a render that would take minutes (the default scene
# at 4000x3000 with 8x8 samples) and must fail in under a second of CPU time
# (user + system: wall time would measure the other tests running beside it)
# with one error line naming the output, leaving nothing behind.
#  - a read-only folder: for root, whom permissions do not stop, a read-only
#    tmpfs mounted on it (or, where mounting is not allowed, the command run
#    as nobody in a folder of mode 555);
#  - /dev/full, an existing device (never removed or replaced);
#  - an existing directory.
set -u
rs="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work/ro"
status=0
as=()
mounted=0
if [ "$(id -u)" = 0 ]; then
  if mount -t tmpfs -o ro,size=64k tmpfs "$work/ro" 2>/dev/null; then
    mounted=1
  else
    chmod 755 "$work"; chmod 555 "$work/ro"
    as=(setpriv --reuid=65534 --regid=65534 --clear-groups)
  fi
else
  chmod 555 "$work/ro"
fi
cleanup() { [ $mounted = 1 ] && umount "$work/ro"; }
trap cleanup EXIT

check() {  # PATTERN OUTPUT
  local pattern="$1" out="$2" err start end rc
  err="$(mktemp)"
  local times; times="$(mktemp)"
  /usr/bin/time -o "$times" -f "%U + %S" \
    "${as[@]}" "$rs" render --size 4000x3000 --spp 8 -o "$out" >/dev/null 2>"$err" </dev/null
  rc=$?
  local secs; secs=$(tail -n 1 "$times" | bc)
  rm -f "$times"
  if [ $rc -eq 0 ] || [ $rc -ge 128 ]; then echo "FAIL: $out: exit code $rc"; status=1; fi
  if [ "$(grep -c '' "$err")" -ne 1 ] || ! grep -Eq -- "$pattern" "$err"; then
    echo "FAIL: $out: stderr does not match /$pattern/ in one line:"; cat "$err"; status=1
  fi
  if [ "$(echo "$secs < 1.0" | bc)" != 1 ]; then echo "FAIL: $out: took $secs s"; status=1; fi
  echo "$out: exit $rc in $secs s: $(cat "$err")"
  rm -f "$err"
}
check "^rayscope: error: .*/ro/x\.png: cannot create a file in '.*/ro': (Read-only file system|Permission denied)$" "$work/ro/x.png"
if [ -n "$(ls -A "$work/ro")" ]; then echo "FAIL: something was left in the read-only folder"; status=1; fi
check "^rayscope: error: /dev/full: exists and is not a regular file$" /dev/full
if [ ! -c /dev/full ]; then echo "FAIL: /dev/full is no longer a device"; status=1; fi
mkdir -p "$work/dir.png"
check "^rayscope: error: .*/dir\.png: is a directory, not an image file$" "$work/dir.png"
exit $status
