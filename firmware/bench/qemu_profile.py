#!/usr/bin/env python3
"""Where the guest instructions go: a per-function (and optionally per-source-line) instruction count from a QEMU
execution log, restricted to the calls of one function of the image. See docs/on-target-cost.md.

Record the log (large: about 170 MB for lashid_bench_estimator), then count:

    qemu-system-arm -machine mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native \
        -icount shift=0 -serial null -d in_asm,exec,nochain -D /tmp/trace.log -kernel <image.elf>
    firmware/bench/qemu_profile.py /tmp/trace.log <image.elf> feed_and_estimate
    firmware/bench/qemu_profile.py /tmp/trace.log <image.elf> estimate_into --windows 256 --stride 2 --lines solve

A window opens when a translation block of a function whose (mangled) name contains PATTERN executes, and closes at
the next block of `main`; everything executed in between (callees included) is counted. --windows limits how many
windows are opened, --stride N counts only every N-th of them. -d in_asm prints each translation block's
instructions when it is translated; -d exec with nochain logs every execution of a block (host address, guest pc,
symbol): the first execution of a new host address belongs to the most recent translation of that pc.
"""
import argparse
import collections
import re
import subprocess

TRACE = re.compile(r"Trace \d+: (0x[0-9a-f]+) \[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/[0-9a-f]+\] ?(.*)")
INSN = re.compile(r"0x([0-9a-f]{8}):")


def count(log, pattern, max_windows, stride):
    pending = collections.deque()  # translations not yet matched to a host address
    blocks = {}  # host address -> guest addresses of its instructions
    current = None
    counts = collections.Counter()
    windows = 0
    inside = False
    with open(log, errors="replace") as f:
        for line in f:
            if line.startswith("IN:"):
                current = []
                pending.append(current)
                continue
            m = INSN.match(line)
            if m and current is not None:
                current.append(int(m.group(1), 16))
                continue
            if not line.startswith("Trace"):
                continue
            current = None
            m = TRACE.match(line)
            host, pc, symbol = m.group(1), int(m.group(2), 16), m.group(3).strip()
            if host not in blocks:
                while pending and (not pending[0] or pending[0][0] != pc):
                    pending.popleft()
                blocks[host] = pending.popleft() if pending else [pc]
            if not inside and pattern in symbol and windows < max_windows:
                inside = True
                windows += 1
            elif inside and symbol == "main":
                inside = False
            if inside and (windows - 1) % stride == 0:
                counts.update(blocks[host])
    return counts, windows


def symbols(elf):
    out = subprocess.run(["arm-none-eabi-nm", "-S", elf], capture_output=True, text=True, check=True).stdout
    table = []
    for line in out.splitlines():
        parts = line.split(" ", 3)
        if len(parts) == 4 and parts[1] and parts[2] in "TtWw":
            table.append((int(parts[0], 16), int(parts[1], 16), parts[3]))
    return table


def demangle(names):
    out = subprocess.run(["arm-none-eabi-c++filt"], input="\n".join(names), capture_output=True, text=True).stdout
    return out.splitlines()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("log")
    parser.add_argument("elf")
    parser.add_argument("pattern", help="substring of the mangled name of the function whose calls are counted")
    parser.add_argument("--windows", type=int, default=1)
    parser.add_argument("--stride", type=int, default=1)
    parser.add_argument("--per", type=float, default=0, help="also print counts divided by this (e.g. samples)")
    parser.add_argument("--lines", metavar="FUNCTION", help="per source line within the functions matching this")
    parser.add_argument("--top", type=int, default=20)
    args = parser.parse_args()

    counts, windows = count(args.log, args.pattern, args.windows, args.stride)
    total = sum(counts.values())
    counted = (windows + args.stride - 1) // args.stride
    print(f"{windows} windows, {counted} counted, {total} instructions, {total / max(counted, 1):.1f} per window")
    table = symbols(args.elf)
    by_function = collections.Counter()
    owner = {}
    for address, n in counts.items():
        name = next((s for start, size, s in table if start <= address < start + size), "?")
        by_function[name] += n
        owner[address] = name
    top = by_function.most_common(args.top)
    for (name, n), pretty in zip(top, demangle([name for name, _ in top])):
        per = f" {n / args.per:9.1f}" if args.per else ""
        print(f"{n:10d}{per}  {pretty[:140]}")

    if args.lines:
        addresses = sorted(a for a in counts if args.lines in owner[a])
        out = subprocess.run(["arm-none-eabi-addr2line", "-a", "-e", args.elf] + [hex(a) for a in addresses],
                             capture_output=True, text=True, check=True).stdout.splitlines()
        by_line = collections.Counter()
        for address_line, location in zip(out[0::2], out[1::2]):
            by_line[location.split("/")[-1]] += counts[int(address_line, 16)]
        print(f"\nper source line (innermost inlined frame; needs an image built with -g) in *{args.lines}*:")
        for location, n in by_line.most_common(args.top):
            print(f"{n:10d}  {location}")


if __name__ == "__main__":
    main()
