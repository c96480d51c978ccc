#!/usr/bin/env bash
# Usage: accel_same_image.sh RAYSCOPE RENDER_OPTIONS...
#
# The structure the rays walk (--accel bvh|bvh2|kdtree|grid|octree|bsp|spheres|
# none, the kD-tree, grid and octree with either --storage, any --loose-factor
# and --kd-split, the BSP tree with each of the three storages) changes how
# much work a render does, never the image: the renders must be the same file, byte
# for byte (PNG of identical pixels), and --stats must report more nodes
# entered by the binary walk (bvh2) than by the 8-wide one (bvh), and none
# without a structure; the kD-tree and grid walks enter nodes (cells) and name
# themselves.
set -euo pipefail
rs="$1"; shift
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for a in bvh bvh2 kdtree grid octree spheres none; do
  "$rs" render -q --stats --accel "$a" "$@" -o "$out/$a.png" > "$out/$a.txt"
done
"$rs" render -q --stats --accel octree --storage smallest-cell "$@" -o "$out/loose.png" > "$out/loose.txt"
"$rs" render -q --stats --accel kdtree --storage smallest-cell "$@" -o "$out/kdloose.png" > "$out/kdloose.txt"
"$rs" render -q --stats --accel kdtree --kd-split median --storage smallest-cell --loose-factor 0.5 "$@" -o "$out/kdmedian.png" > "$out/kdmedian.txt"
"$rs" render -q --stats --accel grid --storage smallest-cell "$@" -o "$out/gridloose.png" > "$out/gridloose.txt"
"$rs" render -q --stats --accel grid --storage smallest-cell --loose-factor 0 "$@" -o "$out/gridloose0.png" > "$out/gridloose0.txt"
"$rs" render -q --stats --accel grid --grid-resolution 7,5,3 "$@" -o "$out/grid753.png" > "$out/grid753.txt"
for st in every-cell smallest-cell split; do
  "$rs" render -q --stats --accel bsp --storage "$st" "$@" -o "$out/bsp-$st.png" > "$out/bsp-$st.txt"
done
for a in bvh2 kdtree grid octree spheres loose kdloose kdmedian gridloose gridloose0 grid753 bsp-every-cell bsp-smallest-cell bsp-split none; do
  cmp "$out/bvh.png" "$out/$a.png" || { echo "FAIL: --accel $a changed the image"; exit 1; }
done
nodes() { sed -n 's/^ *nodes visited *\([0-9]*\).*/\1/p' "$out/$1.txt"; }
n4=$(nodes bvh); n2=$(nodes bvh2); nk=$(nodes kdtree); ng=$(nodes grid); ns=$(nodes spheres); n0=$(nodes none)
echo "nodes visited: bvh $n4, bvh2 $n2, kdtree $nk, grid $ng, spheres $ns, none $n0"
[ -n "$n4" ] && [ -n "$n2" ] && [ -n "$nk" ] && [ -n "$ng" ] && [ -n "$n0" ] || { echo "FAIL: --stats printed no node counts"; cat "$out/bvh.txt"; exit 1; }
[ "$n2" -gt "$n4" ] || { echo "FAIL: the binary walk should enter more nodes than the 8-wide one"; exit 1; }
[ "$nk" -gt 0 ] || { echo "FAIL: the kD-tree walk entered no nodes"; exit 1; }
[ "$ng" -gt 0 ] || { echo "FAIL: the grid walk entered no cells"; exit 1; }
[ -n "$ns" ] && [ "$ns" -gt 0 ] || { echo "FAIL: the sphere tree walk entered no nodes"; exit 1; }
[ "$n0" -eq 0 ] || { echo "FAIL: --accel none entered nodes"; exit 1; }
grep -q "^Walk: *bvh2: .* 2-wide nodes" "$out/bvh2.txt" || { echo "FAIL: --stats does not name the binary walk"; cat "$out/bvh2.txt"; exit 1; }
grep -q "^Walk: *octree, every-cell: " "$out/octree.txt" || { echo "FAIL: --stats does not name the octree walk"; cat "$out/octree.txt"; exit 1; }
grep -q "^Walk: *octree, smallest-cell (loose factor 0.1): " "$out/loose.txt" || { echo "FAIL: --stats does not name the loose octree walk"; cat "$out/loose.txt"; exit 1; }
grep -q "^Walk: *kdtree, sah split, every-cell: " "$out/kdtree.txt" || { echo "FAIL: --stats does not name the kD-tree walk"; cat "$out/kdtree.txt"; exit 1; }
grep -q "^Walk: *kdtree, median split, smallest-cell (loose factor 0.5): " "$out/kdmedian.txt" || { echo "FAIL: --stats does not name the loose median kD-tree walk"; cat "$out/kdmedian.txt"; exit 1; }
grep -q "^Walk: *grid, every-cell: [0-9]* x [0-9]* x [0-9]* cells" "$out/grid.txt" || { echo "FAIL: --stats does not name the grid walk"; cat "$out/grid.txt"; exit 1; }
grep -q "^Walk: *grid, every-cell: 7 x 5 x 3 cells" "$out/grid753.txt" || { echo "FAIL: --grid-resolution 7,5,3 is not the grid's resolution"; cat "$out/grid753.txt"; exit 1; }
grep -q "^Walk: *grid, smallest-cell (loose factor 0.1): .* 1.00 references per primitive" "$out/gridloose.txt" || { echo "FAIL: --stats does not name the loose grid walk"; cat "$out/gridloose.txt"; exit 1; }
for st in every-cell smallest-cell split; do
  grep -q "^Walk: *bsp, $st: [0-9]* nodes" "$out/bsp-$st.txt" || { echo "FAIL: --stats does not name the BSP walk ($st)"; cat "$out/bsp-$st.txt"; exit 1; }
done
grep -q "^Walk: *bsp, split: .* [0-9]* fragments" "$out/bsp-split.txt" || { echo "FAIL: --stats does not count the BSP fragments"; exit 1; }
grep -q "^Walk: *spheres: [0-9]* nodes, [0-9]* leaves" "$out/spheres.txt" || { echo "FAIL: --stats does not name the sphere tree walk"; cat "$out/spheres.txt"; exit 1; }
echo "PASS"
