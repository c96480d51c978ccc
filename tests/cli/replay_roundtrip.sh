#!/usr/bin/env bash
# Usage: replay_roundtrip.sh RAYSCOPE [SCENE] RENDER_OPTIONS... --pixel X,Y
#
# `rayscope render --pixel X,Y` prints the pixel's value and the exact
# `rayscope inspect` command that replays it. Passes when
#  - every setting given to render appears in that command as it was typed
#    (flags such as --texture-filter too)
#    (no float noise such as "--min-contribution 0.00100000005"), and any
#    --min-contribution printed is the shortest text of its float;
#  - running the command (JSON) gives the same color bit for bit (the value is
#    printed as the shortest text that reads back as the same float) and a
#    well-formed ray tree with one primary ray per sample.
set -euo pipefail
rs="$1"; shift
py="${PYTHON:-/usr/bin/python3}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$rs" render -q "$@" -o "$out/img.png" > "$out/render.txt"
value=$(sed -n 's/^pixel ([0-9]*, [0-9]*) = (\(.*\)); its ray tree:$/\1/p' "$out/render.txt")
cmd=$(sed -n 's/^  rayscope inspect \(.*\)$/\1/p' "$out/render.txt")
[ -n "$value" ] && [ -n "$cmd" ] || { echo "render did not print the pixel and command:"; cat "$out/render.txt"; exit 1; }
echo "printed: rayscope inspect $cmd"
args=("$@")
for ((i = 0; i + 1 < ${#args[@]}; i++)); do
  case "${args[i]}" in
    --size|--spp|--max-depth|--min-contribution|--seed|--accel|--storage|--loose-factor|--kd-split|--max-spp|--target-error)
      case " $cmd " in
        *" ${args[i]} ${args[i+1]} "*) ;;
        *) echo "FAIL: the command does not repeat '${args[i]} ${args[i+1]}' as typed"; exit 1 ;;
      esac ;;
  esac
done
for flag in --texture-filter; do
  case " $* " in
    *" $flag "*) case " $cmd " in *" $flag "*) ;; *) echo "FAIL: the command lacks $flag"; exit 1 ;; esac ;;
  esac
done
eval "\"$rs\" inspect $cmd --format json" > "$out/tree.json"
"$py" - "$out/tree.json" "$value" "$cmd" <<'PY'
import json, re, struct, sys
f32 = lambda v: struct.unpack("<f", struct.pack("<f", float(v)))[0]
tree = json.load(open(sys.argv[1]))
want = [f32(v) for v in sys.argv[2].split(",")]
got = [f32(v) for v in tree["color"]]
assert got == want, (got, want)
cutoff = re.search(r"--min-contribution (\S+)", sys.argv[3]).group(1)
# Shortest: no shorter decimal (fewer significant digits) reads back as the same float.
digits = len(re.sub(r"e.*|[-.]", "", cutoff).strip("0")) or 1
assert all(f32(f"{f32(cutoff):.{d}g}") != f32(cutoff) for d in range(1, digits)), cutoff
rays = tree["rays"]
assert rays and rays[0]["kind"] == "primary" and rays[0]["parent"] == -1
ids = {r["id"] for r in rays}
for r in rays:
    for c in r["children"]:
        assert c in ids and rays[c]["parent"] == r["id"]
    assert r["bvh"]["boxes_tested"] >= 0
prim = [r for r in rays if r["parent"] == -1]
n = tree["samples_per_axis"]
if "--max-spp" in sys.argv[3]:  # adaptive: whole batches of the N x N grid, at most all
    b = int(re.search(r"--spp (\d+)", sys.argv[3]).group(1))
    assert 0 < len(prim) <= n * n and len(prim) % (b * b) == 0, (len(prim), n, b)
else:
    assert len(prim) == n * n, (len(prim), n)
print("replayed color", got, "==", want, "bit for bit, with", len(rays), "rays")
PY
