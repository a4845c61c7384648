#!/usr/bin/python3
"""Sizes of the C++ code, counted on the source with its comments, strings and character
literals blanked out (so that a '{' in a literal or a comment is not a brace).

  long-functions.py [N]             functions longer than N lines (default 80), from the
                                    first line of the signature to the closing brace,
                                    longest first, and their count
  long-functions.py --members [N]   classes and structs with more than N data members
                                    (default 15), most first
  long-functions.py --files F...    the same over the given files instead of the tree's
                                    sources (tests/ excluded); with --members likewise
  long-functions.py --self-test     counts a planted file with braces in literals and
                                    comments, initialiser braces and constructors
  long-functions.py --check         the budget the test style.sizes keeps: at most 2
                                    functions over 80 lines and 24 over 50 (tests
                                    excluded), no class of fem/ or mpm/ with more than 15
                                    data members; lists what breaks it, exit 1

Usage: /usr/bin/python3 tools/long-functions.py [--members] [N] [--files F ...]"""
import os
import re
import subprocess
import sys

CONTROL = re.compile(r'^(if|for|while|switch|catch|else|do|try|return)\b')
SCOPE = re.compile(r'(^|[\s>])(namespace|class|struct|union|enum(\s+class)?)\b[^()]*$')
# The end of a function signature: ')' then qualifiers, a trailing return type, or a
# constructor's member initialisers.
SIGNATURE_END = re.compile(
    r'\)\s*(const|override|final|noexcept(\([^)]*\))?|mutable|volatile|&&?|\s)*'
    r'(->\s*[\w:<>,\s*&]+)?\s*$')


def blank(text):
    """The text with comments, string and character literals replaced by spaces (line
    breaks kept, so line numbers stay)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i))
            i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            j = text.find(')' + m.group(1) + '"', i)
            j = n if j < 0 else j + len(m.group(1)) + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c in '"\'':
            # A digit separator (1'000) is not a literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum() \
                    and re.match(r"[0-9a-fA-F]'[0-9a-fA-F]", text[i - 1:i + 2]):
                out.append(' ')
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            j = min(j + 1, n)
            out.append(' ' * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def matching(text, i):
    """The index of the brace that closes the one at i."""
    depth = 0
    for j in range(i, len(text)):
        if text[j] == '{':
            depth += 1
        elif text[j] == '}':
            depth -= 1
            if depth == 0:
                return j
    return len(text) - 1


def is_function(header):
    """Whether a '{' after `header` (at namespace or class scope) opens a function body."""
    if '(' not in header or CONTROL.match(header):
        return False
    if '=' in header.split('(')[0].replace('operator=', ''):
        return False  # a variable initialised by a lambda or a call
    if SIGNATURE_END.search(header):
        return True
    # A constructor's member initialisers, ending with the last one's ')' or '}'.
    return bool(re.search(r'\)\s*:\s*[\w:]', header)) and header.endswith((')', '}'))


def top_level_commas(decl):
    depth = 0
    commas = 0
    for c in decl:
        if c in '<({[':
            depth += 1
        elif c in '>)}]':
            depth -= 1
        elif c == ',' and depth == 0:
            commas += 1
    return commas


def data_members(decl):
    """How many data members a declaration at class scope declares (0 for a function,
    a type, a using, a friend or a static constant)."""
    decl = re.sub(r'^((public|private|protected)\s*:\s*)+', '', decl).strip()
    if not decl or re.match(r'^(using|typedef|friend|template|static|enum|struct|class|union|'
                            r'public|private|protected)\b', decl):
        return 0
    if re.match(r'^(inline\s+)?constexpr\b', decl):
        return 0
    head = decl.split('=')[0]
    if '(' in head:
        return 0  # a function declaration
    first = head
    depth = 0
    for k, c in enumerate(head):
        depth += c in '<({[' and 1 or (c in '>)}]' and -1 or 0)
        if c == ',' and depth == 0:
            first = head[:k]
            break
    if not re.search(r'[\w>\]\*&]\s*[A-Za-z_]\w*\s*(\[[^\]]*\]\s*)?(\{.*\})?\s*$', first):
        return 0
    return 1 + top_level_commas(head)


def scan(text, start=0, end=None, scope='namespace', found=None):
    """Appends the functions and classes between start and end of the blanked text to
    `found` as (kind, name, first line, last line, data members); returns the number of
    data members declared directly in this scope (for a class)."""
    end = len(text) if end is None else end
    found = [] if found is None else found
    line = lambda k: text.count('\n', 0, k) + 1
    header_start = start
    members = 0
    i = start
    while i < end:
        c = text[i]
        if c in ';}':
            if c == ';' and scope == 'class':
                members += data_members(' '.join(text[header_start:i].split()))
            header_start = i + 1
            i += 1
            continue
        if c != '{':
            i += 1
            continue
        raw = text[header_start:i]
        header = ' '.join(raw.split())
        first = header_start + len(raw) - len(raw.lstrip())
        close = matching(text, i)
        scope_match = SCOPE.search(header)
        if header.startswith('extern') or (scope_match and '=' not in header):
            kind = 'namespace' if header.startswith('extern') else scope_match.group(2)
            inner = scan(text, i + 1, close, 'namespace' if kind == 'namespace' else 'class',
                         found)
            if kind in ('class', 'struct', 'union'):
                name = re.search(r'(class|struct|union)\s+([\w:]+)', header)
                found.append(('class', name.group(2) if name else '(anonymous)', line(first),
                              line(close), inner))
            i = close + 1
            header_start = i  # `struct X {...} x;` would declare a member: not used here
            continue
        if is_function(header):
            name = re.search(r'(operator\s*[^\s(]+|[\w:~]+)\s*\(', header)
            found.append(('function', name.group(1) if name else header[:40], line(first),
                          line(close), 0))
            i = close + 1
            header_start = i
            continue
        # A brace initialiser (a variable, a member, a member initialiser of a constructor,
        # a lambda's body in an initialiser): the declaration goes on after it.
        i = close + 1
    return members


def sources(root):
    files = subprocess.check_output(['git', 'ls-files'], cwd=root).decode().split('\n')
    return [os.path.join(root, f) for f in files
            if f.endswith(('.cpp', '.hpp')) and not f.startswith('tests/')]


SELF_TEST = r"""namespace a {
struct S {
  int x{0};
  std::vector<int> v, w;
  double f() const { return 1; }
  static constexpr int k = 3;
  S(int a) : x{a}, v(3) {
    int q = 0;
  }
};
bool parse(const char* s) {
  if (*s == '{') return true;  // a '{' literal
  const char* t = "{{{ /* } */";
  /* { */
  return t[0] == '}' && R"x({)x"[0] == '{';
}
auto lambda = [](int x) {
  return x;
};
}  // namespace a
"""


def self_test():
    found = []
    scan(blank(SELF_TEST), found=found)
    got = sorted((kind, name, last - first + 1, members)
                 for kind, name, first, last, members in found)
    expected = sorted([('class', 'S', 9, 3), ('function', 'f', 1, 0), ('function', 'S', 3, 0),
                       ('function', 'parse', 6, 0)])
    if got != expected:
        print(f'long-functions self-test: counted {got}, expected {expected}')
        sys.exit(1)
    print('long-functions self-test: passed')


BUDGET = [('functions over 80 lines', 80, 2), ('functions over 50 lines', 50, 24)]
MEMBERS_LIMIT = 15


def check(root):
    found = []
    for path in sources(root):
        for item in scan_file(path):
            found.append((os.path.relpath(path, root),) + item)
    failures = 0
    for what, lines, most in BUDGET:
        long = [f for f in found if f[1] == 'function' and f[4] - f[3] + 1 > lines]
        print(f'{what}: {len(long)} (at most {most})')
        if len(long) > most:
            failures += 1
            for f in sorted(long, key=lambda f: f[3] - f[4]):
                print(f'  {f[4] - f[3] + 1:4d}  {f[0]}:{f[3]}  {f[2]}')
    wide = [f for f in found if f[1] == 'class' and f[5] > MEMBERS_LIMIT
            and f[0].startswith(('fem/', 'mpm/'))]
    print(f'classes of fem/ and mpm/ with more than {MEMBERS_LIMIT} data members: {len(wide)} (none)')
    for f in wide:
        failures += 1
        print(f'  {f[5]:4d}  {f[0]}:{f[3]}  {f[2]}')
    sys.exit(1 if failures else 0)


def scan_file(path):
    found = []
    scan(blank(open(path, encoding='utf-8').read()), found=found)
    return found


def main(argv):
    if '--self-test' in argv:
        return self_test()
    if '--check' in argv:
        return check(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
    members_mode = '--members' in argv
    argv = [a for a in argv if a != '--members']
    files = None
    if '--files' in argv:
        k = argv.index('--files')
        files, argv = argv[k + 1:], argv[:k]
    limit = int(argv[0]) if argv else (15 if members_mode else 80)
    rows = []
    for path in files or sources(root):
        text = blank(open(path, encoding='utf-8').read())
        shown = os.path.relpath(path, root) if files is None else path
        found = []
        scan(text, found=found)
        for kind, name, first, last, members in found:
            if members_mode and kind == 'class' and members > limit:
                rows.append((members, shown, first, name))
            elif not members_mode and kind == 'function' and last - first + 1 > limit:
                rows.append((last - first + 1, shown, first, name))
    for n, f, line, name in sorted(rows, reverse=True):
        print(f'{n:4d}  {f}:{line}  {name}')
    what = 'classes with more than {} data members' if members_mode \
        else 'functions longer than {} lines'
    print(f'{len(rows)} {what.format(limit)}')


if __name__ == '__main__':
    main(sys.argv[1:])
