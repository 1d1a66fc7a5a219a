"""Design strings as data in every output: one escaper per output format.

A design's free strings (its ``name``, a ``[motor]`` name and source, ``[prices]`` keys and
currency, designations read from a ``--prices`` file) are written into Markdown, CSV, C,
matplotlib text, SVG/HTML, DXF and JSON. Each writer passes them through the function of its
format here, so that a string can never become structure in the file it lands in: a heading
or a remote image in ``report.md``, a live formula in ``order.csv``, the end of a C comment,
mathtext in a drawing. JSON needs nothing (``json.dumps`` escapes); report.html escapes
with the standard library's ``html.escape`` and the SVG drawings are written by matplotlib,
which escapes XML (both read back in tests/regressions/test_hostile_strings.py).

Plain functions on ``str``; no CAD import. References: CommonMark 0.31 (backslash escapes of
ASCII punctuation, section 2.4), OWASP "CSV Injection" (cells starting with ``= + - @``, tab
or carriage return), ISO C99 6.4.9 (comments end at the first ``*/``) and 6.4.4.4 (octal
escapes), matplotlib "Writing mathematical expressions" (an unescaped ``$`` starts math).
"""

from __future__ import annotations

import unicodedata

#: CommonMark punctuation that starts structure that can fetch or break out inside one line:
#: ``[`` (every link and image, inline or by reference), ``|`` (a table cell) and the
#: backslash itself (else a string ending in one would un-escape the next); ``<`` (raw HTML,
#: autolinks) becomes ``&lt;``. Headings, lists and quotes need a line start, which :func:`one_line` removes;
#: emphasis is cosmetic. Backslash-escaped (section 2.4): each renders as itself.
_MD_SPECIAL = set("\\[|")
#: first characters a spreadsheet reads as a formula (OWASP CSV injection)
_CSV_FORMULA = ("=", "+", "-", "@", "\t", "\r")


def one_line(s: str) -> str:
    """``s`` with every control character (C0, DEL, C1: Unicode category Cc) and line or
    paragraph separator (U+2028, U+2029) replaced by a space: one line of text."""
    return "".join(" " if unicodedata.category(c) in ("Cc", "Zl", "Zp") else c for c in str(s))


def md(s: str) -> str:
    """Text for a Markdown line or table cell: :func:`one_line`, then every character of
    :data:`_MD_SPECIAL` backslash-escaped (renders as itself: no heading, link, image, HTML
    or cell break). Text that is not placed at the start of a line."""
    t = "".join("\\" + c if c in _MD_SPECIAL else c for c in one_line(s))
    return t.replace("<", "&lt;")  # an entity: Python-Markdown has no backslash escape for "<"


def csv_cell(s: str) -> str:
    """A CSV/TSV text cell that a spreadsheet shows as text: a cell starting with one of
    ``= + - @``, tab or carriage return gets a leading ``'`` (OWASP). The csv module quotes
    what else needs quoting."""
    s = str(s)
    return "'" + s if s.startswith(_CSV_FORMULA) else s


def c_comment(s: str) -> str:
    """Text inside a C ``/* ... */`` comment on one line: :func:`one_line`, ``*/`` and
    ``/*`` broken by a space, ``??`` (trigraphs) split, non-ASCII as ``?`` (C99 source
    character set)."""
    t = one_line(s).encode("ascii", "replace").decode("ascii")
    while "*/" in t or "/*" in t or "??" in t:
        t = t.replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")
    return t


def xml_comment(s: str) -> str:
    """Text inside an XML ``<!-- ... -->`` comment on one line: :func:`one_line`, and ``--``
    (not allowed inside a comment, XML 1.0 section 2.5) and a trailing ``-`` broken by a
    space."""
    t = one_line(s)
    while "--" in t:
        t = t.replace("--", "- -")
    return t + " " if t.endswith("-") else t


def c_string(s: str) -> str:
    """The body of a C string literal (without the quotes) whose bytes are the UTF-8 of
    ``s``: printable ASCII as itself, ``\\``, ``"`` and ``?`` escaped, every other byte as
    a three-digit octal escape (C99 6.4.4.4)."""
    out = []
    for b in str(s).encode("utf-8", "surrogatepass"):
        c = chr(b)
        if c in '\\"?':
            out.append("\\" + c)
        elif 0x20 <= b < 0x7F:
            out.append(c)
        else:
            out.append(f"\\{b:03o}")
    return "".join(out)


def mathtext(s: str) -> str:
    """Text for a matplotlib text artist shown as written: :func:`one_line`, every ``$``
    escaped (an unescaped pair starts mathtext; a lone one raised a parse error)."""
    return one_line(s).replace("$", r"\$")
