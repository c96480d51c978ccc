#!/usr/bin/env python3
"""Usage: check_isa_symbols.py BINARY...

The one-binary rule (raytracer/include/rayscope/kernels.h): code compiled for
AVX2 or AVX-512 runs only when the CPU has it. The build keeps every symbol of
the AVX2 and AVX-512 copies of the hot loops local to its copy, except each
copy's table (rayscope::avx2::isa_kernels(), avx512's), whose functions are
called through pointers once the CPU was asked. Were an inline function's AVX
copy left global or weak, the linker could keep it for everyone, baseline code
would call it, and a CPU without AVX would stop there.

This disassembles each BINARY (an executable or a shared library) and fails
when a global or weak function (nm: T or W) other than the tables holds VEX-
or EVEX-encoded instructions. It also fails when a binary holds no AVX code
at all (the kernels are missing, so the check would prove nothing).
"""
import re
import subprocess
import sys

KERNEL_TABLES = re.compile(r"^_ZN8rayscope(4avx2|6avx512)11isa_kernelsEv$")
HEADER = re.compile(r"^([0-9a-f]+) <(.+)>:$")
# A VEX/EVEX instruction: a v-prefixed mnemonic on vector registers.
VEX = re.compile(r"\tv[a-z0-9]+\s+.*%[xyz]mm")


def global_functions(binary):
    """The binary's global and weak functions: mangled name by address."""
    out = subprocess.run(["nm", "--defined-only", binary], capture_output=True, text=True,
                         check=True).stdout
    found = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TW":
            found[int(parts[0], 16)] = parts[2]
    return found


def check(binary):
    globals_ = global_functions(binary)
    dump = subprocess.Popen(["objdump", "-d", "--no-show-raw-insn", binary],
                            stdout=subprocess.PIPE, text=True)
    name, seen, avx, bad = None, False, 0, set()
    for line in dump.stdout:
        m = HEADER.match(line)
        if m:
            name, seen = globals_.get(int(m.group(1), 16)), False
            continue
        if seen or not VEX.search(line):
            continue
        seen = True
        avx += 1
        if name is not None and not KERNEL_TABLES.match(name):
            bad.add(name)
    dump.wait()
    if bad:
        names = subprocess.run(["c++filt"], input="\n".join(sorted(bad)), capture_output=True,
                               text=True).stdout
        print(f"FAIL: {binary}: {len(bad)} global or weak functions hold AVX code:")
        print("\n".join(n[:200] for n in names.splitlines()[:20]))
        return False
    if avx == 0:
        print(f"FAIL: {binary}: no AVX code at all (are the AVX2 and AVX-512 kernels built?)")
        return False
    print(f"PASS: {binary}: {avx} functions hold AVX code, none global or weak")
    return True


if __name__ == "__main__":
    ok = all([check(b) for b in sys.argv[1:]])
    sys.exit(0 if ok else 1)
