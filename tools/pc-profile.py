#!/usr/bin/env python3
"""pc-profile.py - a flat profile from the PCPROF lines of the QEMU plugin
(platform/cortex-m4-bench/insn_count.c, profile=NAME): each executed address
charged to the function symbol holding it (nm -S of the image).

Usage: pc-profile.py --nm arm-none-eabi-nm --elf bench.elf --calls N plugin.txt [--top 15]
Prints "name insns_per_call cycles_est_per_call percent_of_cycles", most cycles first.
"""
import argparse
import bisect
import subprocess


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nm", required=True)
    ap.add_argument("--elf", required=True)
    ap.add_argument("--calls", type=float, required=True, help="calls of the profiled function")
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("plugin")
    a = ap.parse_args()
    syms = []
    for line in subprocess.run([a.nm, "-S", "--defined-only", a.elf], capture_output=True, text=True,
                               check=True).stdout.splitlines():
        f = line.split()
        if len(f) == 4 and f[2] in "tTwW":
            syms.append((int(f[0], 16) & ~1, int(f[1], 16), f[3]))
    syms.sort()
    starts = [s[0] for s in syms]
    insns, cycles = {}, {}
    for line in open(a.plugin):
        f = line.split()
        if not f or f[0] != "PCPROF":
            continue
        pc = int(f[1], 16)
        i = bisect.bisect_right(starts, pc) - 1
        name = syms[i][2] if i >= 0 and pc < syms[i][0] + max(syms[i][1], 2) else "?%x" % pc
        insns[name] = insns.get(name, 0) + int(f[2])
        cycles[name] = cycles.get(name, 0) + int(f[3])
    total = sum(cycles.values()) or 1
    for name in sorted(cycles, key=cycles.get, reverse=True)[:a.top]:
        print("  %-34s %8.0f ins %8.0f cyc est %5.1f %%" % (name, insns[name] / a.calls, cycles[name] / a.calls,
                                                            100.0 * cycles[name] / total))


if __name__ == "__main__":
    main()
