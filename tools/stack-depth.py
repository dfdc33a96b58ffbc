#!/usr/bin/env python3
"""Worst-case stack depth of a function in a linked image (issue 9).

    stack-depth.py --arch avr|arm --objdump TOOL --elf IMAGE.elf --su DIR [--su DIR ...]
                   [--root fc_controller_step] [--target NAME]

Call graph: from the disassembly of the linked image (objdump -d), so that it
is the same on every target and includes the toolchain's routines (libgcc,
libm, libc): AVR call/rcall and jmp/rjmp to another function (a tail call);
Thumb bl/blx and b/b.w to another function. An indirect call (AVR
icall/eicall/ijmp/eijmp, Thumb blx/bx to a register other than lr, a load or
move into pc other than a return or a switch's jump table whose entries all
land in the same function) reachable from the root fails loudly, and so does
recursion (a cycle).

Frames: the -fstack-usage figure of every function compiled by us (the .su
files under the --su directories; every frame there must be static); for a
toolchain routine without one, the frame is read from its disassembly (AVR:
pushes + the frame set up through Y + the return address; Thumb: push, vpush
and sub sp) and marked "est" in the path. AVR figures include the 3-byte
return address of the ATmega2560 (avr-gcc's .su includes it too).

Prints the depth and the deepest path; exit status 1 on a cycle, an
unbounded indirect call, an unknown frame or a dynamic .su frame.
"""
import argparse
import glob
import os
import re
import subprocess
import sys


def fail(msg):
    print("stack-depth: " + msg, file=sys.stderr)
    sys.exit(1)


def canonical(name):
    """foo.constprop.1 and foo.constprop name the same clone in .su and objdump"""
    return re.sub(r"\.\d+(?=\.|$)", "", name)


def read_su(dirs):
    frames = {}
    for d in dirs:
        for path in glob.glob(os.path.join(d, "**", "*.su"), recursive=True):
            with open(path) as fh:
                for line in fh:
                    parts = line.rstrip("\n").split("\t")
                    if len(parts) != 3:
                        continue
                    name = canonical(parts[0].split(":")[-1])
                    if parts[2] != "static":
                        fail("%s: frame of %s is %s" % (path, name, parts[2]))
                    # a static function of the same name in two files: keep the larger
                    frames[name] = max(frames.get(name, 0), int(parts[1]))
    return frames


FUNC_RE = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")
INSN_RE = re.compile(r"^\s*([0-9a-f]+):\s+(?:[0-9a-f]{2,8} )+\s*([a-z][a-z0-9.]*)\s*(.*)$")
TARGET_RE = re.compile(r"(?:0x)?([0-9a-f]+)\s+<([^>]+)>")
STARTS = {}
# avr-libc's math routines whose bodies the soft-float code jumps into
LIBM_TAILS = {"atan2", "atan", "sqrt", "sin", "cos", "fabs", "ldexp", "frexp", "fmod"}
CURRENT = [0, 0]


def disassemble(objdump, elf):
    text = subprocess.run([objdump, "-d", "--no-show-raw-insn", elf], check=True,
                          capture_output=True, text=True).stdout
    funcs, starts = {}, {}
    current = None
    for line in text.splitlines():
        m = FUNC_RE.match(line)
        if m:
            current = m.group(2)
            funcs[current] = []
            starts[int(m.group(1), 16)] = current
            continue
        if current is None:
            continue
        m = re.match(r"^\s*([0-9a-f]+):\s+([a-z][a-z0-9.]*)\s*(.*)$", line)
        if m:
            funcs[current].append((m.group(2), m.group(3)))
            continue
        m = re.match(r"^\s*[0-9a-f]+:\s+\.word\s+0x([0-9a-f]+)", line)
        if m:  # data in the code: the entries of a jump table (analyse_arm)
            funcs[current].append((".word", m.group(1)))
    return funcs, starts


def target_of(operands):
    """The function a direct branch goes to: None for a local branch (inside
    the same function), the name for the start of a function, and a failure
    for a jump into the middle of another one."""
    m = TARGET_RE.findall(operands)
    if not m:
        return "?"
    address = int(m[-1][0], 16)
    if address in STARTS:
        return STARTS[address]
    return None if CURRENT[0] <= address < CURRENT[1] else "?" + m[-1][1]


def analyse_avr(name, insns):
    calls, indirect = set(), []
    pushes, frame = 0, 0
    r26 = r27 = None
    saves = False
    for i, (op, args) in enumerate(insns):
        if op in ("call", "rcall", "jmp", "rjmp"):
            t = target_of(args)
            if t is None:
                continue
            if t.startswith("?<__prologue_saves__+") or t.startswith("?__prologue_saves__+"):
                # -mcall-prologues enters the save routine part way: fewer
                # registers than its 18, so 18 stays an upper bound
                saves = True
            elif t.startswith("?<__epilogue_restores__+") or t.startswith("?__epilogue_restores__+"):
                pass
            elif t.startswith("?") and "+" in t and t[1:].split("+")[0] in STARTS.values():
                # a jump into the body of another function: libgcc's and avr-libc's
                # hand-written soft-float routines share their tails so (a jump,
                # no return address, within the frame of the routine that was
                # called, which is counted where it is called); anything else is
                # bounded by the whole function jumped into, an over-estimate
                into = t[1:].split("+")[0]
                if op in ("jmp", "rjmp") and (into.startswith("__") or into in LIBM_TAILS):
                    continue
                calls.add(into)
            elif t.startswith("?"):
                indirect.append(op + " " + args)
            elif t == "__prologue_saves__":
                saves = True
            elif t != name and t != "__epilogue_restores__":
                calls.add(t)
        elif op in ("icall", "eicall", "ijmp", "eijmp"):
            indirect.append(op)
        elif op == "push":
            pushes += 1
        elif op in ("sbiw", "subi") and args.startswith("r28"):
            # the frame through Y: in r28, 0x3d / in r29, 0x3e then sbiw/subi
            before = [a for _, a in insns[max(0, i - 4):i]]
            if any("0x3d" in a for a in before):
                n = int(args.split(",")[1].strip().split()[0], 0)
                frame += n if op == "sbiw" else (n & 0xFF)
        elif op == "ldi" and args.startswith("r26,"):
            r26 = int(args.split(",")[1].strip().split()[0], 0)
        elif op == "ldi" and args.startswith("r27,"):
            r27 = int(args.split(",")[1].strip().split()[0], 0)
    size = 3 + pushes + frame
    if saves:
        # libgcc's __prologue_saves__: 18 registers, then the frame in r27:r26
        size = 3 + 18 + ((r27 or 0) << 8 | (r26 or 0))
    return calls, indirect, size


def jump_table_stays_inside(insns, i):
    """insns[i] is ldr pc, [rX, rY, lsl #2]: a switch's jump table when the
    instruction before set rX to a pc-relative address (adr) and the table
    words that follow (after an alignment nop) all land inside the function
    being analysed; then it is a jump within the function, no call."""
    m = re.match(r"^pc,\s*\[(r\d+),\s*(r\d+),\s*lsl\s*#2\]$", insns[i][1].strip())
    if not m or i == 0:
        return False
    before_op, before_args = insns[i - 1]
    if before_op.split(".")[0] not in ("add", "adr") or \
            not re.match(r"^%s,\s*pc\b" % m.group(1), before_args.strip()):
        return False
    # the table's length from the bound check on the index (cmp rY, #N: N + 1
    # entries) when there is one: literal words may follow the table
    count = None
    for op, args in reversed(insns[max(0, i - 6):i - 1]):
        bound = re.match(r"^%s,\s*#(\d+)" % m.group(2), args.strip())
        if op.split(".")[0] == "cmp" and bound:
            count = int(bound.group(1)) + 1
            break
    entries = []
    for op, args in insns[i + 1:]:
        if count is not None and len(entries) == count:
            break
        if op == ".word":
            entries.append(int(args, 16) & ~1)  # the Thumb bit
        elif op == "nop" and not entries:
            continue
        else:
            break
    return bool(entries) and all(CURRENT[0] <= e < CURRENT[1] for e in entries)


def analyse_arm(name, insns):
    calls, indirect = set(), []
    size = 0
    for i, (op, args) in enumerate(insns):
        base = op.split(".")[0]
        if base in ("bl", "blx", "b") or re.match(r"^b(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)$", base):
            if base == "blx" and not TARGET_RE.search(args):
                indirect.append(op + " " + args)
                continue
            t = target_of(args)
            if t is None:
                continue
            if t.startswith("?"):
                indirect.append(op + " " + args)
            elif t != name:
                calls.add(t)
        elif base == "bx" and args.strip() != "lr":
            indirect.append(op + " " + args)
        elif base in ("mov", "ldr") and re.match(r"^pc\b", args.strip()) and \
                not re.match(r"^pc,\s*\[sp\],\s*#4$", args.strip()) and \
                not jump_table_stays_inside(insns, i):
            # (ldr pc, [sp], #4 is a return; a switch's table jump stays inside)
            indirect.append(op + " " + args)
        elif base in ("push", "stmdb") and "{" in args:
            size += 4 * len(expand_regs(args))
        elif base == "vpush":
            regs = expand_regs(args)
            size += sum(8 if r.startswith("d") else 4 for r in regs)
        elif base == "sub" and re.match(r"^sp,\s*(sp,\s*)?#\d+", args.strip()):
            size += int(args.split("#")[1].split()[0].rstrip(";"), 0)
    return calls, indirect, size


def expand_regs(args):
    inner = args[args.index("{") + 1:args.index("}")]
    regs = []
    for part in inner.split(","):
        part = part.strip()
        m = re.match(r"^([a-z]+)(\d+)-[a-z]*(\d+)$", part)
        if m:
            regs += [m.group(1) + str(k) for k in range(int(m.group(2)), int(m.group(3)) + 1)]
        elif part:
            regs.append(part)
    return regs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--arch", choices=("avr", "arm"), required=True)
    ap.add_argument("--objdump", required=True)
    ap.add_argument("--elf", required=True)
    ap.add_argument("--su", action="append", default=[])
    ap.add_argument("--root", default="fc_controller_step")
    ap.add_argument("--target", default="")
    a = ap.parse_args()

    su = read_su(a.su)
    funcs, starts = disassemble(a.objdump, a.elf)
    STARTS.update(starts)
    ranges = sorted(starts)
    bounds = {starts[x]: (x, ranges[i + 1] if i + 1 < len(ranges) else 1 << 40) for i, x in enumerate(ranges)}
    if a.root not in funcs:
        fail("%s not in %s" % (a.root, a.elf))
    analyse = analyse_avr if a.arch == "avr" else analyse_arm
    info = {}

    def node(name):
        if name not in info:
            if name not in funcs:
                fail("call to %s, which has no code in %s" % (name, a.elf))
            CURRENT[:] = bounds[name]
            calls, indirect, est = analyse(name, funcs[name])
            if name == "__tablejump2__":
                # libgcc's switch dispatch: it is jumped to (not called) and its
                # eijmp lands on a case label inside the function that jumped
                indirect, est = [], 0
            if indirect:
                fail("%s: indirect call or jump that cannot be bounded: %s" % (name, "; ".join(indirect)))
            if canonical(name) in su:
                info[name] = (calls, su[canonical(name)], False)
            else:
                info[name] = (calls, est, True)
        return info[name]

    best = {}  # name -> (depth, path)
    on_path = []

    def depth(name):
        if name in on_path:
            fail("recursion: " + " -> ".join(on_path[on_path.index(name):] + [name]))
        if name in best:
            return best[name]
        on_path.append(name)
        calls, frame, est = node(name)
        deepest = (0, [])
        for c in sorted(calls):
            d = depth(c)
            if d[0] > deepest[0]:
                deepest = d
        on_path.pop()
        best[name] = (frame + deepest[0], [(name, frame, est)] + deepest[1])
        return best[name]

    total, path = depth(a.root)
    estimated = sorted(n for n, (_, _, e) in info.items() if e)
    tag = (a.target + ": ") if a.target else ""
    print("%sworst-case stack of %s: %d bytes (%d functions reachable, no recursion, no indirect calls)"
          % (tag, a.root, total, len(info)))
    print("  deepest path: " + " -> ".join("%s %d%s" % (n, f, " est" if e else "") for n, f, e in path))
    if estimated:
        print("  frames read from the disassembly (no .su): " + ", ".join(estimated))


if __name__ == "__main__":
    main()
