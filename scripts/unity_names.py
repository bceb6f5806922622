#!/usr/bin/env python3
"""Names a unity build may capture silently.

In a unity build (QUIVER_UNITY_BUILD) a target's files are compiled in batches, one translation
unit each. A name one file declares in its anonymous namespace is then visible to the files after
it in the batch, and an unqualified lookup there finds it before a name of an enclosing namespace
or of a `using namespace` (the codec's flag kClaim was once found as another file's enumerator).
Clashes of the same name in the same scope fail to compile; these do not.

    scripts/unity_names.py BUILD_DIR [REVIEWED_FILE]

prints each "NAME: declared in A, used in B" (heuristic: top-level declarations of anonymous
namespaces; uses outside comments and strings, not qualified) that REVIEWED_FILE does not list,
and exits 1 if there is any. Review each: rename it, or add the line with why it is harmless.
"""
import glob, os, re, sys
root = sys.argv[1]
reviewed = set()
if len(sys.argv) > 2:
    for line in open(sys.argv[2]):
        line = line.split('#')[0].strip()
        if line: reviewed.add(line)
def rel(path):
    # the path inside the source tree (or the build tree, for generated files)
    for base in (src_root, root):
        if path.startswith(base + '/'): return path[len(base) + 1:]
    return path
src_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
def strip(text):
    # comments and string literals out (raw strings too), so that only code is searched
    text = re.sub(r'R"(\w*)\((?:.|\n)*?\)\1"', '""', text)
    text = re.sub(r'//[^\n]*', '', text)
    text = re.sub(r'/\*(?:.|\n)*?\*/', '', text)
    text = re.sub(r'"(?:\\.|[^"\\\n])*"', '""', text)
    return text
def anon_blocks(text):
    out = []
    for m in re.finditer(r'^namespace \{\s*$', text, re.M):
        depth = 0; i = m.end()
        # find matching close: track braces from the namespace's {
        j = text.index('{', m.start()); depth = 0
        k = j
        while k < len(text):
            c = text[k]
            if c == '{': depth += 1
            elif c == '}':
                depth -= 1
                if depth == 0: break
            k += 1
        out.append(text[j+1:k])
    return out
decl_res = [
    r'^\s*(?:inline\s+)?(?:static\s+)?(?:constexpr|const)\s+[\w:<>,\s\*&]+?\b(\w+)\s*(?:=|\[|\{)',
    r'^\s*(?:enum(?:\s+class)?|struct|class|union)\s+(\w+)',
    r'^\s*using\s+(\w+)\s*=',
    r'^(?:[\w:<>,\*&]+\s+)+\**&?(\w+)\s*\([^;]*$',
]
def top_level(block):
    # the block's text at brace depth 0, enum bodies kept (their enumerators are top-level names)
    out = []; depth = 0; i = 0; keep_depth = None
    while i < len(block):
        c = block[i]
        if c == '{':
            head = block[max(0, i-200):i]
            if depth == 0 and re.search(r'enum(?:\s+class)?\s+\w*\s*(?::\s*[\w:]+\s*)?$', head) and 'enum class' not in head[-60:]:
                keep_depth = 1
            depth += 1
            if depth == 1: out.append('{')
        elif c == '}':
            depth -= 1
            if depth == 0:
                out.append('}'); keep_depth = None
        elif depth == 0 or (keep_depth is not None and depth == keep_depth):
            out.append(c)
        i += 1
    return ''.join(out)
def declared(block):
    block = top_level(block)
    names = set()
    for rx in decl_res:
        for m in re.finditer(rx, block, re.M):
            names.add(m.group(1))
    # enumerators of plain enums
    for m in re.finditer(r'enum\s+\w*\s*(?::\s*[\w:]+\s*)?\{([^}]*)\}', block):
        for e in m.group(1).split(','):
            e = e.split('=')[0].strip()
            if re.match(r'^\w+$', e): names.add(e)
    return names - {'main', 'if', 'for', 'while', 'switch', 'return', 'operator'}
found = set()
unities = sorted(glob.glob(root + '/**/Unity/unity_*_cxx.cxx', recursive=True))
if not unities:
    sys.exit(f"unity_names.py: no unity sources under {root} (is QUIVER_UNITY_BUILD on?)")
for unity in unities:
    files = re.findall(r'#include "([^"]+)"', open(unity).read())
    texts = {f: open(f, errors='replace').read() for f in files}
    code = {f: strip(t) for f, t in texts.items()}
    decls = {f: set().union(*[declared(b) for b in anon_blocks(texts[f])]) if anon_blocks(texts[f]) else set() for f in files}
    for i, a in enumerate(files):
        for x in sorted(decls[a]):
            for b in files[i+1:]:
                if x in decls[b]: continue
                if re.search(r'(?<![\w.:>])%s\b' % re.escape(x), code[b]):
                    found.add(f"{x}: declared in {rel(a)}, used in {rel(b)}")
new = sorted(found - reviewed)
for line in new:
    print(line)
print(f"unity_names.py: {len(unities)} unity sources, {len(found)} names seen in later files, "
      f"{len(found) - len(new)} reviewed, {len(new)} to review", file=sys.stderr)
sys.exit(1 if new else 0)
