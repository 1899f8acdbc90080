#!/usr/bin/env python3
"""Instruction counts of a board image under qemu, per function and per instruction (scripts/profile-on-board).

report.py IMAGE.elf COUNTS [--top N] [--function SUBSTRING] [--per N]
COUNTS is the plugin's "address count" lines. Prints the functions that ran the most instructions; with --function,
the disassembly of the first function whose demangled name contains SUBSTRING, each instruction with its count
divided by --per (e.g. the particle-beams of the phase measured) and the function's total.
"""
import argparse
import bisect
import collections
import subprocess


def symbols(elf):
    out = subprocess.run(['arm-none-eabi-nm', '-C', '--defined-only', '-n', elf], capture_output=True, text=True,
                         check=True).stdout
    syms = []
    for line in out.splitlines():
        parts = line.split(' ', 2)
        if len(parts) == 3 and parts[1] in 'tTwW':
            syms.append((int(parts[0], 16) & ~1, parts[2]))
    return syms


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('elf')
    ap.add_argument('counts')
    ap.add_argument('--top', type=int, default=20)
    ap.add_argument('--function')
    ap.add_argument('--per', type=float, default=1.0)
    a = ap.parse_args()
    syms = symbols(a.elf)
    starts = [s[0] for s in syms]
    per_addr = collections.Counter()
    with open(a.counts) as f:
        for line in f:
            addr, runs = line.split()
            per_addr[int(addr, 16)] += int(runs)
    per_fn = collections.Counter()
    for addr, runs in per_addr.items():
        i = bisect.bisect_right(starts, addr) - 1
        per_fn[syms[i][1] if i >= 0 else '?'] += runs
    total = sum(per_fn.values())
    print(f'{total} instructions in all')
    for name, runs in per_fn.most_common(a.top):
        print(f'{runs:14d} {100.0 * runs / total:5.1f} %  {name[:140]}')
    if not a.function:
        return
    match = [k for k, s in enumerate(syms) if a.function in s[1]]
    if not match:
        raise SystemExit(f'report.py: no function contains "{a.function}"')
    k = match[0]
    lo, hi = syms[k][0], syms[k + 1][0] if k + 1 < len(syms) else syms[k][0] + 0x10000
    dis = subprocess.run(['arm-none-eabi-objdump', '-d', '-C', '--no-show-raw-insn', f'--start-address={lo:#x}',
                          f'--stop-address={hi:#x}', a.elf], capture_output=True, text=True, check=True).stdout
    print(f'\n{syms[k][1]}: instructions per {a.per:g} (runs / --per), then the instruction')
    in_fn = 0
    for line in dis.splitlines():
        head = line.strip().split(':', 1)[0]
        try:
            addr = int(head, 16)
        except ValueError:
            continue
        runs = per_addr.get(addr, 0)
        in_fn += runs
        print(f'{runs / a.per:10.2f} {line.strip()[:150]}')
    print(f'{in_fn / a.per:10.2f} in all, per {a.per:g}')


if __name__ == '__main__':
    main()
