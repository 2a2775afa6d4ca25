#!/usr/bin/env python3
"""Writes the benchmarks' tables into the documentation pages, so no measured number in docs/
is typed by hand.

A page marks each generated table with a pair of comments:

    <!-- bench-table: summary.md#Fastest run per error target -->
    | ... the table, replaced on every run ... |
    <!-- /bench-table -->

`summary.md` is a file of the benchmark output folder; after `#` an optional heading of that
file, whose first table is taken (without it: the file's first table).

    scripts/update_docs_tables.py [--only <file.md>] <benchmark output folder> <page.md> [<page.md> ...]

--only rewrites just the tables taken from that file (after one benchmark's own run), leaving
the page's other tables as they are.

Exits 1, changing nothing in that page, when a marked source or its table is missing.
"""
import os
import re
import sys

MARK = re.compile(r'^<!-- bench-table: (?P<file>[^#>]+?)(?:#(?P<heading>[^>]+?))? -->\s*$')
END = '<!-- /bench-table -->'


def first_table(lines):
    table, inside = [], False
    for line in lines:
        if line.startswith('|'):
            table.append(line)
            inside = True
        elif inside:
            break
    return table


def table_from(folder, name, heading):
    path = os.path.join(folder, name.strip())
    if not os.path.exists(path):
        raise LookupError(f'{path} does not exist')
    lines = open(path).read().splitlines()
    if heading:
        starts = [i for i, l in enumerate(lines) if l.lstrip('#').strip() == heading.strip()
                  and l.startswith('#')]
        if not starts:
            raise LookupError(f'{path} has no heading "{heading.strip()}"')
        lines = lines[starts[0] + 1:]
    table = first_table(lines)
    if not table:
        raise LookupError(f'{path} has no table' + (f' under "{heading.strip()}"' if heading else ''))
    return table


def update(page, folder, only=None):
    lines = open(page).read().splitlines()
    out, i, count = [], 0, 0
    while i < len(lines):
        match = MARK.match(lines[i])
        out.append(lines[i])
        i += 1
        if not match or (only and match['file'].strip() != only):
            continue
        end = next((j for j in range(i, len(lines)) if lines[j].strip() == END), None)
        if end is None:
            raise LookupError(f'{page}: "{lines[i - 1]}" has no {END}')
        out.extend(table_from(folder, match['file'], match['heading']))
        out.append(lines[end])
        i = end + 1
        count += 1
    open(page, 'w').write('\n'.join(out) + '\n')
    return count


def main(argv):
    only = None
    if len(argv) > 2 and argv[1] == '--only':
        only = argv[2]
        argv = argv[:1] + argv[3:]
    if len(argv) < 3:
        print(__doc__)
        return 2
    status = 0
    for page in argv[2:]:
        try:
            print(f'{page}: {update(page, argv[1], only)} tables written from {argv[1]}')
        except LookupError as error:
            print(f'{page}: not updated: {error}', file=sys.stderr)
            status = 1
    return status


if __name__ == '__main__':
    sys.exit(main(sys.argv))
