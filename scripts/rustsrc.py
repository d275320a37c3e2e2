"""Rust source read as the structure checks need it (`check-module-cycles.py`,
`check-fn-lines.py`): comments and literals blanked with the lines kept, and test code (the item
after each `#[cfg(test)]`) told from the rest. A lexer of a few dozen lines, not a parser: the
checks need items and paths, not types.
"""
import re

IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
RAW = re.compile(r'b?r(#*)"')
CHAR = re.compile(r"'(\\(x[0-9a-fA-F]{2}|u\{[0-9a-fA-F]*\}|.)|[^\\'])'")
WORD = re.compile(r"[A-Za-z0-9_]")
ATTR = re.compile(r"\s*#\s*\[")
USE = re.compile(r"\s*(pub(\s*\([^)]*\))?\s+)?use\b")
TEST_ATTR = re.compile(r"#\s*\[\s*cfg\s*\(\s*test\s*\)\s*\]")


def blank(text):
    """The text with comments removed and string and char literals emptied, lines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    out.append("\n" if text[i] == "\n" else "")
                    i += 1
        elif c in "br" and (m := RAW.match(text, i)) and (i == 0 or not WORD.match(text[i - 1])):
            end = text.find('"' + m.group(1), i + m.end())
            end = n if end < 0 else end + 1 + len(m.group(1))
            out.append('""' + "\n" * text.count("\n", i, end))
            i = end
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j + 1
        elif c == "'":
            # A char literal ('a', '\n', '"'), else a lifetime or a label ('a).
            m = CHAR.match(text, i)
            if m:
                out.append("' '")
                i = m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def item_end(code, start):
    """Where the item starting at `start` ends: its `;` or its block's closing brace."""
    i = start
    while True:
        m = ATTR.match(code, i)
        if not m:
            break
        depth, i = 1, m.end()
        while i < len(code) and depth:
            depth += {"[": 1, "]": -1}.get(code[i], 0)
            i += 1
    is_use = USE.match(code, i) is not None
    depth = 0
    while i < len(code):
        c = code[i]
        if c in "([":
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == ";" and depth <= 0:
            return i + 1
        elif c == "{" and depth <= 0 and not is_use:
            braces = 0
            while i < len(code):
                braces += {"{": 1, "}": -1}.get(code[i], 0)
                i += 1
                if braces == 0:
                    return i
        elif c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
        i += 1
    return len(code)


def split_tests(code):
    """(code without its test items, names of the modules declared `#[cfg(test)] mod name;`)."""
    kept, test_mods, pos = [], set(), 0
    for m in TEST_ATTR.finditer(code):
        if m.start() < pos:
            continue
        end = item_end(code, m.end())
        item = code[m.end():end]
        decl = re.fullmatch(r"\s*(?:#\s*\[[^\]]*\]\s*)*(?:pub(?:\s*\([^)]*\))?\s+)?mod\s+(" + IDENT + r")\s*;", item)
        if decl:
            test_mods.add(decl.group(1))
        kept.append(code[pos:m.start()])
        kept.append("\n" * item.count("\n"))
        pos = end
    kept.append(code[pos:])
    return "".join(kept), test_mods
