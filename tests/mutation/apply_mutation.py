#!/usr/bin/env python3
"""Reads the mutation list and applies one mutation, or lists them.

  apply_mutation.py LIST list                 -> "id<TAB>file<TAB>suite<TAB>note" per mutation
  apply_mutation.py LIST apply ID SOURCE_ROOT -> replaces the fragment in the file (exactly one
                                                 occurrence, or the one named by `occurrence:`)

The list is blocks separated by blank lines; '#' lines before a block are its comment (what the
mutation breaks); keys: id, file, from, to, suite, optional occurrence (1-based) and note (why a
survivor cannot be killed or does not matter).
"""
import sys


def parse(path):
    mutations, block, comment = [], {}, []
    def flush():
        nonlocal block, comment
        if block:
            for key in ("id", "file", "from", "to", "suite"):
                if key not in block:
                    sys.exit(f"{path}: mutation {block.get('id', '?')} has no '{key}:'")
            block["comment"] = " ".join(comment)
            mutations.append(block)
        block, comment = {}, []
    for raw in open(path, encoding="utf-8"):
        line = raw.rstrip("\n")
        if not line.strip():
            flush()
        elif line.startswith("#"):
            if block:
                flush()
            comment.append(line.lstrip("# ").strip())
        else:
            key, sep, value = line.partition(":")
            if not sep:
                sys.exit(f"{path}: cannot read line {line!r}")
            value = value[1:] if value.startswith(" ") else value
            block[key.strip()] = value
    flush()
    ids = [m["id"] for m in mutations]
    if len(ids) != len(set(ids)):
        sys.exit(f"{path}: duplicate ids")
    return mutations


def main():
    mutations = parse(sys.argv[1])
    if sys.argv[2] == "list":
        for m in mutations:
            print("\t".join([m["id"], m["file"], m["suite"], m.get("note", "")]))
        return
    if sys.argv[2] != "apply":
        sys.exit("usage: apply_mutation.py LIST list | apply ID SOURCE_ROOT")
    m = next((m for m in mutations if m["id"] == sys.argv[3]), None)
    if m is None:
        sys.exit(f"no mutation {sys.argv[3]}")
    path = f"{sys.argv[4]}/{m['file']}"
    text = open(path, encoding="utf-8").read()
    count = text.count(m["from"])
    occurrence = int(m.get("occurrence", "0"))
    if occurrence == 0 and count != 1:
        sys.exit(f"{m['id']}: the fragment occurs {count} times in {m['file']} (need exactly 1 or 'occurrence:')")
    if occurrence > count:
        sys.exit(f"{m['id']}: occurrence {occurrence} asked, the fragment occurs {count} times")
    at = -1
    for _ in range(max(occurrence, 1)):
        at = text.index(m["from"], at + 1)
    text = text[:at] + m["to"] + text[at + len(m["from"]):]
    open(path, "w", encoding="utf-8").write(text)


if __name__ == "__main__":
    main()
