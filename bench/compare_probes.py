#!/usr/bin/python3
"""Compares two probes.csv files of the same case (e.g. --device cpu and --device cuda): for each column,
the largest difference over all rows relative to the largest magnitude in the first file.

    python3 bench/compare_probes.py REFERENCE.csv OTHER.csv [--tolerance 1e-8]

Prints one markdown row per column and exits with 1 when a relative difference exceeds the tolerance or
the files differ in rows or columns.
"""
import csv
import sys


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def main():
    args = sys.argv[1:]
    tolerance = 1e-8
    if "--tolerance" in args:
        i = args.index("--tolerance")
        tolerance = float(args[i + 1])
        del args[i : i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    head_a, a = read(args[0])
    head_b, b = read(args[1])
    if head_a != head_b or len(a) != len(b):
        print(f"<!-- {args[0]} and {args[1]} differ in columns or rows ({len(a)} against {len(b)}) -->")
        sys.exit(1)
    worst_all = 0.0
    print(f"| {args[0]} vs {args[1]} | rows | largest |value| | largest difference | relative |")
    print("|---|---:|---:|---:|---:|")
    for c, name in enumerate(head_a):
        scale = max(abs(r[c]) for r in a)
        worst = max(abs(ra[c] - rb[c]) for ra, rb in zip(a, b))
        relative = worst / scale if scale > 0 else worst
        worst_all = max(worst_all, relative)
        print(f"| {name} | {len(a)} | {scale:.6g} | {worst:.3g} | {relative:.3g} |")
    sys.exit(0 if worst_all <= tolerance else 1)


if __name__ == "__main__":
    main()
