#!/usr/bin/python3
"""Lists the functions of the C++ sources (tests excluded) longer than N lines (default
80), counted from the signature's first line to the closing brace, longest first.
Usage: /usr/bin/python3 tools/long-functions.py [N]"""
import os, re, sys, subprocess
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
limit = int(sys.argv[1]) if len(sys.argv) > 1 else 80
files = [f for f in subprocess.check_output(['git', 'ls-files'], cwd=root).decode().split('\n')
         if f.endswith(('.cpp', '.hpp')) and not f.startswith('tests/')]
out = []
for f in files:
    lines = open(os.path.join(root, f)).read().split('\n')
    i = 0
    while i < len(lines):
        l = lines[i]
        # a definition starts at column 0 (or 2 inside a class) and its body opens with '{'
        if re.match(r'^(  )?[A-Za-z].*\)\s*(const)?\s*(override)?\s*(noexcept)?\s*\{\s*$', l) or \
           (re.match(r'^(  )?[A-Za-z][^;]*\($', l) or re.match(r'^(  )?[A-Za-z][^;]*\([^;]*,$', l)):
            # find the opening brace line
            start = i
            while i < len(lines) and not lines[i].rstrip().endswith('{'):
                i += 1
            if i >= len(lines): break
            if re.match(r'^\s*(namespace|struct|class|enum|union|extern|if|for|while|switch|else|return|case)\b', lines[start]): i += 1; continue
            depth = 0; j = i
            while j < len(lines):
                depth += lines[j].count('{') - lines[j].count('}')
                if depth <= 0: break
                j += 1
            n = j - start + 1
            if n > limit:
                name = re.search(r'([\w:~]+)\s*\(', lines[start])
                out.append((n, f, start + 1, name.group(1) if name else lines[start][:40]))
            i = j + 1
            continue
        i += 1
for n, f, line, name in sorted(out, reverse=True):
    print(f'{n:4d}  {f}:{line}  {name}')
