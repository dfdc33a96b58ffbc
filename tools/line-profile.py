#!/usr/bin/env python3
"""Line profile of a bench image: cycles per instruction address mapped onto
source lines by addr2line.

    tools/line-profile.py --elf bench.elf --pc-cycles pc.txt [--top 40]
        ATmega2560: avr_bench's --pc-cycles output ("0xADDRESS cycles_per_call")
    tools/line-profile.py --elf bench.elf --pcprof plugin.txt --calls 16 \
        --addr2line arm-none-eabi-addr2line --nm arm-none-eabi-nm
        Cortex-M4F: the QEMU plugin's PCPROF lines ("PCPROF address insns
        est_cycles", summed over the timed calls; divided by --calls)

--chain DEPTH adds the cycles by inlined call chain (fc_controller_step >
fly_rotors > allocate > ...): where a whole library is inlined into one
function (the Cortex-M4F's one translation unit) this is the by-module view.

bench.elf must carry debug lines (-g; -g does not change the code gcc emits,
so its cycles are the bench image's). tools/avr-line-profile.sh builds one for
the ATmega and runs it. Prints the cycles per call of the profiled function charged to
each source line (inlined code is charged to the line it came from), most
first, and the same summed per function (the function the code is in, after
inlining). libgcc's routines (no line information) are charged to their symbol.
"""
import argparse
import bisect
import collections
import os
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--elf", required=True)
    source = ap.add_mutually_exclusive_group(required=True)
    source.add_argument("--pc-cycles", help="avr_bench --pc-cycles FILE")
    source.add_argument("--pcprof", help="the M4F plugin's output file (PCPROF lines)")
    ap.add_argument("--calls", type=int, default=1, help="timed calls the PCPROF sums are over")
    ap.add_argument("--top", type=int, default=40)
    ap.add_argument("--addr2line", default="avr-addr2line")
    ap.add_argument("--nm", default="avr-nm")
    ap.add_argument("--chain", type=int, default=0, metavar="DEPTH",
                    help="also the cycles by the chain of inlined calls, outermost first, to DEPTH calls "
                         "(a library inlined into one function, as the Cortex-M4F's, by module)")
    args = ap.parse_args()

    rows = []
    if args.pc_cycles:
        with open(args.pc_cycles) as f:
            for line in f:
                addr, cycles = line.split()
                rows.append((addr, float(cycles)))
    else:
        with open(args.pcprof) as f:
            for line in f:
                fields = line.split()
                if len(fields) == 4 and fields[0] == "PCPROF":
                    rows.append(("0x" + fields[1], float(fields[3]) / args.calls))
    if not rows:
        sys.exit("no cycles in " + (args.pc_cycles or args.pcprof))
    out = subprocess.run([args.addr2line, "-f", "-e", args.elf] + [a for a, _ in rows],
                         check=True, capture_output=True, text=True).stdout.splitlines()
    if len(out) != 2 * len(rows):
        sys.exit("addr2line gave %d lines for %d addresses" % (len(out), len(rows)))
    # the code symbols, for the libgcc routines (no line information: addr2line
    # would name the last line before them)
    symbols = []
    for line in subprocess.run([args.nm, "-n", "--defined-only", args.elf], check=True, capture_output=True,
                               text=True).stdout.splitlines():
        fields = line.split()
        # the linker's weak markers (__stack, __heap_end) are addresses in RAM,
        # not code: as symbols they would split the function that holds them
        if len(fields) == 3 and fields[1] in "tTwW" and fields[2] not in ("__stack", "__heap_end"):
            symbols.append((int(fields[0], 16), fields[2]))
    starts = [a for a, _ in symbols]
    holders = [bisect.bisect_right(starts, int(a, 16)) - 1 for a, _ in rows]
    no_lines = symbols_without_lines(args, sorted({symbols[k] for k in holders if k >= 0}), symbols)
    per_line = collections.Counter()
    per_func = collections.Counter()
    total = 0.0
    for i, (_, cycles) in enumerate(rows):
        func, where = out[2 * i], out[2 * i + 1]
        where = where.split(" ")[0]
        k = holders[i]
        holder = symbols[k][1] if k >= 0 else "?"
        if holder.startswith("__"):
            func, where = holder, "libgcc:0"
        elif holder in no_lines:
            func, where = holder, "asm:0"
        path, _, number = where.rpartition(":")
        per_line["%s:%s (%s)" % (os.path.basename(path) or "?", number, func)] += cycles
        per_func[func] += cycles
        total += cycles
    print("cycles per call: %.0f" % total)
    print("\nby source line (function of the code), top %d:" % args.top)
    for key, cycles in per_line.most_common(args.top):
        print("  %8.0f %5.1f %%  %s" % (cycles, 100.0 * cycles / total, key))
    print("\nby function (after inlining), top %d:" % args.top)
    for key, cycles in per_func.most_common(args.top):
        print("  %8.0f %5.1f %%  %s" % (cycles, 100.0 * cycles / total, key))
    if args.chain > 0:
        per_chain = collections.Counter()
        for (_, cycles), chain in zip(rows, inline_chains(args, [a for a, _ in rows])):
            per_chain[" > ".join(chain[:args.chain + 1])] += cycles
        print("\nby inlined call chain (outermost first, %d deep), top %d:" % (args.chain, args.top))
        for key, cycles in per_chain.most_common(args.top):
            print("  %8.0f %5.1f %%  %s" % (cycles, 100.0 * cycles / total, key))


def symbols_without_lines(args, symbols, all_symbols):
    """The code symbols with no line information of their own (routines in
    assembly): addr2line names, at their first address, another function
    that is a symbol of its own, the last one before them that has lines
    (an inlined function's name, at the start of a .part copy, is not one)."""
    if not symbols:
        return set()
    out = subprocess.run([args.addr2line, "-f", "-e", args.elf] + ["0x%x" % a for a, _ in symbols],
                         check=True, capture_output=True, text=True).stdout.splitlines()
    named = {name.split(".")[0] for _, name in all_symbols}
    return {name for (_, name), func in zip(symbols, out[0::2])
            if func != name.split(".")[0] and func in named}


def inline_chains(args, addresses):
    """For each address the functions it lies in, outermost first: the
    function that holds the code, then each call inlined into it down to the
    function the instruction came from (addr2line -i, which lists them
    innermost first, each address's list opened by the address itself)."""
    out = subprocess.run([args.addr2line, "-a", "-i", "-f", "-e", args.elf] + addresses,
                         check=True, capture_output=True, text=True).stdout.splitlines()
    chains = []
    i = 0
    while i < len(out):
        i += 1  # the address
        names = []
        while i < len(out) and not out[i].startswith("0x"):
            names.append(out[i])
            i += 2  # the function's name, then its line
        chains.append(list(reversed(names)))
    if len(chains) != len(addresses):
        sys.exit("addr2line -i gave %d chains for %d addresses" % (len(chains), len(addresses)))
    return chains


if __name__ == "__main__":
    main()
