#!/usr/bin/env python3
"""Compares two runs of scripts/reference_run.sh column by column: every result column (state
hashes, errors, residuals, iteration and step counts, outcomes) must be equal as written;
timing columns (milliseconds, seconds, rates, speed-ups, bandwidths) and the wall times inside
the stress table's details are left out. Exits 1 when any result differs.

    scripts/compare_reference_runs.py <before dir> <after dir>
"""
import csv
import glob
import os
import re
import sys

TIMING = {'step_s', 'ms_per_step', 's_per_simulated_s', 'factor_s', 'speedup_over_explicit',
          'wall_seconds'}


def is_timing(column):
    c = column.lower()
    return (c in TIMING or c.startswith('ms') or c.startswith('cpu_ms') or c.endswith('_ms')
            or 'seconds' in c or 'over' in c or 'gbs' in c or 'bandwidth' in c
            or 'per_second' in c or 'speedup' in c)


def without_wall_time(value):
    return re.sub(r'[0-9.]+ s wall', '', value or '')


def main(before, after):
    files = sorted(os.path.relpath(p, before)
                   for p in glob.glob(os.path.join(before, '**', '*.csv'), recursive=True))
    if not files:
        print(f'no CSV files under {before}')
        return 1
    differing = 0
    for rel in files:
        rows_before = list(csv.DictReader(open(os.path.join(before, rel))))
        path_after = os.path.join(after, rel)
        if not os.path.exists(path_after):
            print(f'{rel}: missing in {after}')
            differing += 1
            continue
        rows_after = list(csv.DictReader(open(path_after)))
        if len(rows_before) != len(rows_after):
            print(f'{rel}: {len(rows_before)} rows before, {len(rows_after)} after')
            differing += 1
            continue
        columns = [c for c in (rows_before[0].keys() if rows_before else []) if not is_timing(c)]
        diffs = [(i, c, a[c], b.get(c)) for i, (a, b) in enumerate(zip(rows_before, rows_after))
                 for c in columns if without_wall_time(a[c]) != without_wall_time(b.get(c))]
        print(f'{rel}: {len(rows_before)} rows, {len(columns)} result columns, '
              f'{len(diffs)} differences')
        for row, column, old, new in diffs[:8]:
            print(f'    row {row} {column}: {old} -> {new}')
        differing += bool(diffs)
    print(f'files with differences: {differing}')
    return 1 if differing else 0


if __name__ == '__main__':
    if len(sys.argv) != 3:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
