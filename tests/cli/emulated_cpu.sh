#!/usr/bin/env bash
# Usage: emulated_cpu.sh RAYSCOPE OUT_DIR CPU LEVEL SCENE
# The one binary on an older CPU: runs `rayscope render` on an x86-64 CPU that
# QEMU emulates (qemu-x86_64 -cpu CPU: qemu64 has SSE2 only, Nehalem SSE4.2,
# max AVX2 but no AVX-512), where an instruction the CPU lacks stops the
# program (SIGILL). Passes when the render picks the LEVEL kernels, writes the
# image this machine renders natively, byte for byte, and when asking for a
# level above the emulated CPU's gives one error line and a non-zero exit.
set -u
rayscope="$1"; out="$2"; cpu="$3"; level="$4"; scene="$5"
mkdir -p "$out"
args=(render "$scene" --size 64x48 --spp 2 -q)
status=0
"$rayscope" "${args[@]}" -o "$out/native.png" || { echo "FAIL: native render"; exit 1; }
qemu-x86_64 -cpu "$cpu" "$rayscope" "${args[@]}" --stats -o "$out/$cpu.png" >"$out/$cpu.txt" 2>&1
rc=$?
if [ $rc -ne 0 ]; then echo "FAIL: exit code $rc on $cpu:"; cat "$out/$cpu.txt"; exit 1; fi
if ! grep -Eq "^Kernels: +$level " "$out/$cpu.txt"; then
  echo "FAIL: expected the $level kernels on $cpu:"; grep "^Kernels" "$out/$cpu.txt"; status=1
fi
if ! cmp -s "$out/native.png" "$out/$cpu.png"; then
  echo "FAIL: the image on $cpu differs from the native one"; status=1
fi
if [ "$level" != avx512 ]; then
  RAYSCOPE_ISA=avx512 qemu-x86_64 -cpu "$cpu" "$rayscope" "${args[@]}" -o "$out/$cpu-above.png" \
    >/dev/null 2>"$out/$cpu-above.txt"
  rc=$?
  if [ $rc -eq 0 ] || [ $rc -ge 128 ]; then echo "FAIL: RAYSCOPE_ISA=avx512 on $cpu exited $rc"; status=1; fi
  if [ "$(grep -c '' "$out/$cpu-above.txt")" -ne 1 ] ||
    ! grep -q "RAYSCOPE_ISA=avx512: this CPU runs at most $level" "$out/$cpu-above.txt"; then
    echo "FAIL: expected one error line naming RAYSCOPE_ISA:"; cat "$out/$cpu-above.txt"; status=1
  fi
  if [ -e "$out/$cpu-above.png" ]; then echo "FAIL: an image was written"; status=1; fi
fi
[ $status -eq 0 ] && echo "PASS: $cpu ran the $level kernels and rendered the native image"
exit $status
