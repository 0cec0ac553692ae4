#!/usr/bin/env python3
"""Every relative link and image in the repository's Markdown files points at a file that exists,
and a link to a heading of a Markdown file (file.md#heading) names a heading it has.

    scripts/check-doc-links.py            # the tracked *.md files of the tree this script is in
    scripts/check-doc-links.py ROOT       # another tree (its git-tracked files, or every *.md)

Links inside fenced code blocks and inline code are not links. Absolute URLs (http:, https:,
mailto:) are not checked (no network). Headings become anchors as GitHub makes them: lower case,
punctuation other than '-' and '_' dropped, spaces to '-', a repeated heading suffixed -1, -2.
Prints one line per broken link (file:line: target: why) and exits 1 if there is any, 0 otherwise.
Element folders keep their own page (skyelements/<name>/README.md) and its images: a link into
an element folder that is not in the tree at all (the element deleted, as CI's removal step does)
is counted apart, not broken — an element is optional, its folder all or nothing.
"""
import os
import re
import subprocess
import sys

root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..'))
try:
    files = subprocess.run(['git', '-C', root, 'ls-files', '*.md'], check=True, capture_output=True, text=True).stdout.split()
except (subprocess.CalledProcessError, FileNotFoundError):
    files = []
if not files:  # not a git checkout (or nothing tracked under root): every *.md, build folders aside
    for d, dirs, fs in os.walk(root):
        dirs[:] = [x for x in dirs if not x.startswith(('build', '.git'))]
        files += [os.path.relpath(os.path.join(d, f), root) for f in fs if f.endswith('.md')]
files = [f for f in files if os.path.exists(os.path.join(root, f))]

fence = re.compile(r'^\s*(```|~~~)')
inline_code = re.compile(r'`[^`]*`')
link = re.compile(r'!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
heading = re.compile(r'^(#{1,6})\s+(.*?)\s*#*\s*$')


def slug(text):
    text = re.sub(r'`([^`]*)`', r'\1', text)
    text = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', text)  # a link in a heading: its text
    text = re.sub(r'<[^>]+>', '', text).strip().lower()
    text = re.sub(r'[^\w\- ]', '', text, flags=re.UNICODE)
    return text.replace(' ', '-')


anchors_cache = {}


def anchors(path):
    if path not in anchors_cache:
        seen, out, in_fence = {}, set(), False
        with open(path, encoding='utf-8') as f:
            for line in f:
                if fence.match(line):
                    in_fence = not in_fence
                    continue
                m = None if in_fence else heading.match(line)
                if m:
                    s = slug(m.group(2))
                    n = seen.get(s, 0)
                    out.add(s if n == 0 else f'{s}-{n}')
                    seen[s] = n + 1
                for a in re.findall(r'<a\s+(?:name|id)="([^"]+)"', line):
                    out.add(a)
        anchors_cache[path] = out
    return anchors_cache[path]


def absent_element(dest):
    """True when dest lies in skyelements/<name>/ and that folder is not in the tree."""
    parts = os.path.relpath(dest, root).split(os.sep)
    return len(parts) > 2 and parts[0] == 'skyelements' and not os.path.isdir(os.path.join(root, 'skyelements', parts[1]))


broken = absent = 0
for rel in sorted(files):
    path = os.path.join(root, rel)
    in_fence = False
    with open(path, encoding='utf-8') as f:
        lines = f.readlines()
    for no, line in enumerate(lines, 1):
        if fence.match(line):
            in_fence = not in_fence
            continue
        if in_fence:
            continue
        for target in link.findall(inline_code.sub('', line)):
            if re.match(r'^[a-zA-Z][a-zA-Z0-9+.-]*:', target):
                continue
            file_part, _, frag = target.partition('#')
            dest = path if not file_part else os.path.normpath(os.path.join(os.path.dirname(path), file_part))
            if not os.path.exists(dest) and absent_element(dest):
                absent += 1
            elif not os.path.exists(dest):
                print(f'{rel}:{no}: {target}: no such file')
                broken += 1
            elif frag and dest.endswith('.md') and frag not in anchors(dest):
                print(f'{rel}:{no}: {target}: no heading "#{frag}" in {os.path.relpath(dest, root)}')
                broken += 1
print(f'check-doc-links: {len(files)} Markdown files, {broken} broken link(s)'
      + (f', {absent} into element folders not in this tree' if absent else ''))
sys.exit(1 if broken else 0)
