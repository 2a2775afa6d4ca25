#!/usr/bin/env python3
"""Checks that the pvpython names the documentation writes exist in the plugin's XML.

    tests/docs/check_doc_names.py [--root DIR] [page.md ...]

Reads xml/*.xml (no ParaView needed) and, in README.md and docs/*.md (or the pages given), the
code: fenced and indented code blocks and inline `code` spans. In that code it checks

* every call `Name(` or `simple.Name(`: one of our proxies under the name pvpython gives it (its
  label with spaces and punctuation removed, e.g. SoftBodyVoxelize for the proxy
  VoxelizeSurface), or a ParaView / VTK function this script knows (KNOWN_CALLS);
* every keyword `Property=` of a call to one of our proxies: a property of that proxy;
* every `variable.Property =` where the variable was bound to one of our proxies earlier in the
  page (`body = SoftBody(...)`): a property of that proxy; an unbound variable with a
  capitalized attribute: a property of one of our proxies;
* every inline span that is a whole assignment, `` `Property = value` ``: a property of one of
  our proxies;
* every quoted value assigned to a property with an enumeration (`Method="XPBD"`,
  `body.Collisions = 'Obstacles + Bodies'`) and every `` `Property` = `Value` `` of the prose:
  one of that enumeration's entries;
* the first column of every table headed "Property": properties of our proxies.

Exits 1 naming the page, the line and the unknown name for each problem; prints how many names
it checked.
"""
import argparse
import glob
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

# ParaView's paraview.simple functions, readers and filters, and the VTK methods, that the pages
# call; a call that is neither this nor one of our proxies is reported, so a misspelt proxy
# cannot pass as someone else's function.
KNOWN_CALLS = {
    'AppendDatasets', 'Box', 'Delaunay3D', 'GetActiveView', 'GetAnimationScene', 'Hide',
    'LoadPlugin', 'LoadState', 'OpenDataFile', 'OutputPort', 'Plane', 'Render', 'SaveData',
    'SaveScreenshot', 'SaveState', 'Show', 'Sphere', 'Transform', 'XMLPolyDataReader',
    'XMLUnstructuredGridReader',
}
# Names ours are recognised by when they are not in the XML (a misspelt or renamed proxy).
OURS = re.compile(r'SoftBody|Tetrahedraliz|Voxeliz|TetGen|Gmsh', re.IGNORECASE)


def python_name(label):
    """The name pvpython gives a proxy or property with this label."""
    return ''.join(c for c in label if c.isalnum() or c == '_')


class Proxy:
    def __init__(self, element, path):
        self.name = element.get('name')
        self.call = python_name(element.get('label') or self.name)
        self.path = path
        self.properties = {}  # pvpython name -> enumeration texts (None: no enumeration)
        for child in element:
            if not child.tag.endswith('Property') or not child.get('name'):
                continue
            texts = None
            for domain in child.iter('EnumerationDomain'):
                texts = {entry.get('text') for entry in domain.iter('Entry')}
            for key in {child.get('name'), python_name(child.get('label') or child.get('name'))}:
                self.properties[key] = texts


def read_proxies(xml_dir):
    proxies = []
    for path in sorted(glob.glob(os.path.join(xml_dir, '*.xml'))):
        for group in ElementTree.parse(path).getroot().iter('ProxyGroup'):
            proxies.extend(Proxy(e, path) for e in group if e.get('name'))
    return proxies


def code_regions(lines):
    """(text, first line number) of each fenced block, indented block and inline code span."""
    regions, i = [], 0
    while i < len(lines):
        line = lines[i]
        if line.lstrip().startswith('```'):
            j = i + 1
            while j < len(lines) and not lines[j].lstrip().startswith('```'):
                j += 1
            regions.append(('\n'.join(lines[i + 1:j]), i + 2))
            i = j + 1
            continue
        indented = re.match(r'( {4,}|\t)\S', line)
        if indented and (i == 0 or not lines[i - 1].strip()):
            j = i
            while j < len(lines) and (re.match(r'( {4,}|\t)\S', lines[j]) or (
                    not lines[j].strip() and j + 1 < len(lines)
                    and re.match(r'( {4,}|\t)\S', lines[j + 1]))):
                j += 1
            regions.append(('\n'.join(lines[i:j]), i + 1))
            i = j
            continue
        for span in re.finditer(r'(`+)(.+?)\1', line):
            regions.append((span.group(2), i + 1))
        i += 1
    return regions


def matching_paren(text, start):
    """Index of the parenthesis closing the one at start (or len(text))."""
    depth, quote, i = 0, None, start
    while i < len(text):
        c = text[i]
        if quote:
            if c == '\\':
                i += 1
            elif c == quote:
                quote = None
        elif c in '"\'':
            quote = c
        elif c == '#':
            while i < len(text) and text[i] != '\n':
                i += 1
            continue
        elif c in '([{':
            depth += 1
        elif c in ')]}':
            depth -= 1
            if depth == 0:
                return i
        i += 1
    return len(text)


def top_level_arguments(text):
    """(offset, argument) of each comma-separated argument at depth 0."""
    parts, depth, quote, begin = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            if c == quote:
                quote = None
        elif c in '"\'':
            quote = c
        elif c in '([{':
            depth += 1
        elif c in ')]}':
            depth -= 1
        elif c == ',' and depth == 0:
            parts.append((begin, text[begin:i]))
            begin = i + 1
    parts.append((begin, text[begin:]))
    return parts


def blank_strings(text):
    """text with the inside of every string literal replaced by spaces (same offsets)."""
    return re.sub(r'''(["'])(?:\\.|(?!\1).)*?\1''', lambda m: m.group(1) + ' ' * (len(m.group(0)) - 2)
                  + m.group(1), text)


STRING = re.compile(r'''^\s*(?P<q>["'])(?P<value>[^"']*)(?P=q)''')


class Checker:
    def __init__(self, proxies):
        self.by_call = {p.call: p for p in proxies}
        self.by_xml_name = {p.name: p for p in proxies}
        self.all_properties = {}
        for p in proxies:
            for key, texts in p.properties.items():
                self.all_properties.setdefault(key, set())
                if texts:
                    self.all_properties[key] |= texts
        self.errors = []
        self.checked = []  # (page, line, kind, name) of every name checked, for --list
        self.counts = {'proxy calls': 0, 'properties': 0, 'enumeration values': 0}

    def error(self, page, line, message):
        self.errors.append(f'{page}:{line}: {message}')

    def property_known(self, page, line, proxy, key):
        self.counts['properties'] += 1
        self.checked.append((page, line, 'property', key))
        names = proxy.properties if proxy else self.all_properties
        if key not in names:
            where = f'proxy {proxy.name} ({proxy.path})' if proxy else 'any proxy of xml/*.xml'
            self.error(page, line, f'unknown property "{key}": not a property of {where}')
            return False
        return True

    def value_known(self, page, line, proxy, key, value):
        texts = (proxy.properties if proxy else self.all_properties).get(key)
        if not texts:
            return
        self.counts['enumeration values'] += 1
        self.checked.append((page, line, 'value', f'{key} = "{value}"'))
        if value not in texts:
            self.error(page, line, f'unknown value "{value}" of {key}: the XML has '
                       + ', '.join(f'"{t}"' for t in sorted(texts)))

    def check_code(self, page, text, first_line, bindings):
        def line_of(offset):
            return first_line + text.count('\n', 0, offset)

        # Calls are searched for outside string literals ('GPU (EGL)' is a value, not a call).
        code = blank_strings(text)
        calls = list(re.finditer(r'(?<![\w.])(?:simple\.)?([A-Z]\w*)\(', code))
        # Only a region that calls ParaView or our proxies is pvpython; elsewhere (a formula,
        # a folder tree) a capitalized word before a parenthesis is reported only when it
        # looks like one of ours.
        pvpython = any(c.group(1) in KNOWN_CALLS or c.group(1) in self.by_call for c in calls)
        for call in calls:
            name, line = call.group(1), line_of(call.start())
            proxy = self.by_call.get(name)
            if proxy is None:
                if name in self.by_xml_name:
                    self.counts['proxy calls'] += 1
                    self.error(page, line, f'"{name}(" is the XML name of proxy {name}; '
                               f'pvpython calls it {self.by_xml_name[name].call}(')
                elif OURS.search(name) or (pvpython and name not in KNOWN_CALLS):
                    self.counts['proxy calls'] += 1
                    self.error(page, line, f'unknown proxy "{name}(": no proxy of xml/*.xml is '
                               'called so in pvpython, nor is it a ParaView function this check knows')
                continue
            self.counts['proxy calls'] += 1
            self.checked.append((page, line, 'proxy', name))
            bound = re.search(r'(\w+)\s*=\s*(?:simple\.)?$', text[:call.start()].split('\n')[-1])
            if bound:
                bindings[bound.group(1)] = proxy
            open_paren = call.end() - 1
            inner = text[open_paren + 1:matching_paren(text, open_paren)]
            for offset, argument in top_level_arguments(inner):
                keyword = re.match(r'\s*([A-Za-z_]\w*)\s*=(?!=)', argument)
                if not keyword:
                    continue
                at = line_of(open_paren + 1 + offset + keyword.start(1))
                if self.property_known(page, at, proxy, keyword.group(1)):
                    value = STRING.match(argument[keyword.end():])
                    if value:
                        self.value_known(page, at, proxy, keyword.group(1), value.group('value'))

        for assignment in re.finditer(r'(?<![\w.])(\w+)\.([A-Za-z_]\w*)\s*=(?!=)', code):
            variable, key = assignment.group(1), assignment.group(2)
            proxy = bindings.get(variable)
            if proxy is None and (variable in bindings or not key[0].isupper()):
                continue  # a ParaView object's or a Python attribute
            line = line_of(assignment.start())
            if self.property_known(page, line, proxy, key):
                value = STRING.match(text[assignment.end():])
                if value:
                    self.value_known(page, line, proxy, key, value.group('value'))

        for binding in re.finditer(r'(?<![\w.])(\w+)\s*=\s*(?:simple\.)?([A-Z]\w*)\(', code):
            if binding.group(2) not in self.by_call:
                bindings[binding.group(1)] = None  # bound to someone else's object

    def check_prose(self, page, lines):
        header = None
        for number, line in enumerate(lines, 1):
            # A span that is a whole assignment, `Property = value`, e.g. `TimeStep = 0`.
            for span in re.finditer(r"`([A-Z]\w*) = ([^`=]+)`", line):
                key, value = span.groups()
                if self.property_known(page, number, None, key):
                    quoted = STRING.match(value)
                    if quoted:
                        self.value_known(page, number, None, key, quoted.group('value'))
            # `Property` = `Value` in a sentence.
            for pair in re.finditer(r'`([A-Za-z]\w*)` = `([^`]+)`', line):
                key, value = pair.groups()
                if self.all_properties.get(key):
                    self.value_known(page, number, None, key, value)
            # A table of properties: its first column names them.
            if not line.startswith('|'):
                header = None
                continue
            cells = [c.strip() for c in line.strip().strip('|').split('|')]
            if header is None:
                header = cells[0]
                continue
            if header == 'Property' and not set(cells[0]) <= set('-: '):
                for key in re.findall(r'`([^`]+)`', cells[0]):
                    self.property_known(page, number, None, key)

    def check_page(self, page, shown):
        lines = open(page, encoding='utf-8').read().splitlines()
        bindings = {}
        for text, first_line in code_regions(lines):
            self.check_code(shown, text, first_line, bindings)
        self.check_prose(shown, lines)


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--root', default=os.path.dirname(os.path.dirname(here)),
                        help='the repository (xml/, README.md, docs/)')
    parser.add_argument('--list', action='store_true', help='print every name checked')
    parser.add_argument('pages', nargs='*', help='pages to check (default: README.md, docs/*.md)')
    args = parser.parse_args(argv)

    proxies = read_proxies(os.path.join(args.root, 'xml'))
    if not proxies:
        print(f'no proxies found in {args.root}/xml/*.xml')
        return 1
    pages = args.pages or [os.path.join(args.root, 'README.md')] + sorted(
        glob.glob(os.path.join(args.root, 'docs', '*.md')))
    checker = Checker(proxies)
    for page in pages:
        shown = os.path.relpath(page, args.root) if not args.pages else page
        checker.check_page(page, shown)

    if args.list:
        for page, line, kind, name in checker.checked:
            print(f'{page}:{line}: {kind} {name}')
    counts = ', '.join(f'{n} {what}' for what, n in checker.counts.items())
    print(f'{len(pages)} pages against {len(proxies)} proxies of xml/*.xml: checked {counts} '
          f'({sum(checker.counts.values())} names)')
    for message in checker.errors:
        print(message)
    if checker.errors:
        print(f'{len(checker.errors)} documented names are not in the XML')
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
