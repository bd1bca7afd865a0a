#!/usr/bin/env python3
"""Quality per byte (issue #41's goal tables) from `probebake eval --csv` files of one scene.

usage: scripts/eval_per_byte.py TITLE DEFAULT.csv [MORE.csv ...]
The files are runs of the same scene and receivers, e.g. the default sweep and `--svo-depth 3` and `4`.
For each rung of lookup bytes (16 K, 64 K, 256 K, 1 M), the best row that fits it, by relative RMSE with
the l2 probe code (`l2_relative_rmse`, bytes `l2_lookup_bytes`): among the grid engine's rows of the first
file (the baseline as grid engines run it), and among the adaptive methods' SVO rows of every file whose
seam score meets issue #39's goal (seam p99 <= 0.01). Prints a markdown table.
"""
import csv
import sys

RUNGS = [16_000, 64_000, 256_000, 1_000_000]
SEAM_GOAL = 0.01


def rows(path, first):
    out = []
    for r in csv.DictReader(open(path)):
        if r["sampler"] == "all-probes":
            continue
        depth = "" if first else f" (SVO depth {r['svo_depth']})"
        out.append({"name": r["label"] + depth, "sampler": r["sampler"], "placement": r["placement"],
                    "probes": int(r["probes"]), "bytes": int(r["l2_lookup_bytes"]),
                    "rel": float(r["l2_relative_rmse"]), "seam": float(r["seam_p99"]), "first": first})
    return out


def best(candidates, rung):
    fitting = [r for r in candidates if r["bytes"] <= rung]
    return min(fitting, key=lambda r: r["rel"]) if fitting else None


def cell(r):
    return f"{r['name']}: {r['probes']} probes, {r['bytes']:,} B | {r['rel']:.4f}" if r else "none fits | –"


def main():
    title, files = sys.argv[1], sys.argv[2:]
    everything = [r for i, f in enumerate(files) for r in rows(f, i == 0)]
    grid = [r for r in everything if r["sampler"] == "grid" and r["first"]]
    adaptive = [r for r in everything if r["sampler"] == "svo" and r["placement"] != "grid" and r["seam"] <= SEAM_GOAL]
    print(f"**{title}**\n")
    print("| lookup bytes ≤ | grid engine | rel. RMSE | adaptive, seam p99 ≤ 0.01 | rel. RMSE | adaptive / grid |")
    print("|--:|---|--:|---|--:|--:|")
    for rung in RUNGS:
        g, a = best(grid, rung), best(adaptive, rung)
        ratio = f"{a['rel'] / g['rel']:.2f}×" if a and g else "–"
        print(f"| {rung:,} | {cell(g)} | {cell(a)} | {ratio} |")
    print()


if __name__ == "__main__":
    main()
