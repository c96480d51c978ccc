#!/usr/bin/env bash
# Usage: same_output.sh PREFIX -- COMMAND... FLAG
# Runs COMMAND -o PREFIX.plain.exr, then COMMAND FLAG -o PREFIX.flag.exr, and
# passes when both runs succeed and write the same image: the same size and
# channels (oiiotool --info -v, without the file name and time stamp) and the
# same pixels in every channel (idiff, no tolerance). FLAG changes what is
# printed, not what is written.
set -euo pipefail
prefix="$1"; shift 2
flag="${*: -1}"
cmd=("${@:1:$#-1}")
rm -f "$prefix.plain.exr" "$prefix.flag.exr"
"${cmd[@]}" -o "$prefix.plain.exr" > /dev/null
"${cmd[@]}" "$flag" -o "$prefix.flag.exr" > /dev/null
info() { oiiotool --info -v "$1" | sed -e 1d -e '2s/^[^:]*:/:/' | grep -v DateTime; }
if ! diff <(info "$prefix.plain.exr") <(info "$prefix.flag.exr"); then
  echo "FAIL: '$flag' changed the size, channels or metadata of the output file"
  exit 1
fi
if ! idiff -fail 0 -warn 0 "$prefix.plain.exr" "$prefix.flag.exr"; then
  echo "FAIL: '$flag' changed the pixels of the output file"
  exit 1
fi
echo "ok: '$flag' writes the same image: $(info "$prefix.flag.exr" | grep 'channel list')"
