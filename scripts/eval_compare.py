#!/usr/bin/env python3
"""Side by side: two `probebake eval --csv` files of the same scene and receivers (before, after).

usage: scripts/eval_compare.py BEFORE.csv AFTER.csv [TITLE]
Prints a markdown table: probes, relative RMSE, max error, coverage before -> after, and the after file's
seam p99 when it has that column. Rows are matched by (label, sampler).
"""
import csv
import sys


def rows(path):
    return {(r["label"], r["sampler"]): r for r in csv.DictReader(open(path))}


def main():
    before, after = rows(sys.argv[1]), rows(sys.argv[2])
    title = sys.argv[3] if len(sys.argv) > 3 else "config"
    seams = any("seam_p99" in r for r in after.values())
    head = f"| {title} | sampler | probes | rel. RMSE | max error (W/m²) | coverage |"
    print(head + (" seam p99 |" if seams else ""))
    print("|---|---|--:|--:|--:|--:|" + ("--:|" if seams else ""))
    g = lambda x: f"{float(x):.3g}"
    for key, a in after.items():
        b = before.get(key)
        if b is None:
            continue
        line = (f"| {key[0]} | {key[1]} | {a['probes']} | {g(b['relative_rmse'])} → {g(a['relative_rmse'])} | "
                f"{g(b['max_error'])} → {g(a['max_error'])} | {g(b['coverage'])} → {g(a['coverage'])} |")
        if seams:
            s = float(a.get("seam_p99", -1))
            line += f" {'-' if s < 0 else f'{s:.4f}'} |"
        print(line)


if __name__ == "__main__":
    main()
