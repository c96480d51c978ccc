#!/usr/bin/env bash
# `rayscope render --pixel X,Y` prints the pixel's value and the exact
# `rayscope inspect` command that replays it; running that command (JSON) must
# give the same color, bit for bit as printed with 6 significant digits, and a
# well-formed ray tree.
set -euo pipefail
rs="$1"; shift
py="${PYTHON:-/usr/bin/python3}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$rs" render -q "$@" -o "$out/img.png" > "$out/render.txt"
value=$(sed -n 's/^pixel ([0-9]*, [0-9]*) = (\(.*\)); its ray tree:$/\1/p' "$out/render.txt")
cmd=$(sed -n 's/^  rayscope inspect \(.*\)$/\1/p' "$out/render.txt")
[ -n "$value" ] && [ -n "$cmd" ] || { echo "render did not print the pixel and command:"; cat "$out/render.txt"; exit 1; }
eval "\"$rs\" inspect $cmd --format json" > "$out/tree.json"
"$py" - "$out/tree.json" "$value" <<'PY'
import json, sys
tree = json.load(open(sys.argv[1]))
want = [float(v) for v in sys.argv[2].split(",")]
got = tree["color"]
assert all(abs(g - w) <= 5e-6 * max(1.0, abs(w)) for g, w in zip(got, want)), (got, want)
rays = tree["rays"]
assert rays and rays[0]["kind"] == "primary" and rays[0]["parent"] == -1
ids = {r["id"] for r in rays}
for r in rays:
    for c in r["children"]:
        assert c in ids and rays[c]["parent"] == r["id"]
    assert r["bvh"]["boxes_tested"] >= 0
prim = [r for r in rays if r["parent"] == -1]
n = tree["samples_per_axis"]
assert len(prim) == n * n, (len(prim), n)
print("replayed color", got, "==", want, "with", len(rays), "rays")
PY
