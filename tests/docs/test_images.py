"""Every image in README.md and docs/ shows on the code host and on the docs site.

Rules (issue 34 item 4):
* every image target (Markdown ``![..](path)`` or raw ``<img src="path">``) names a file that
  exists, relative to the page;
* raw ``<img>`` only in ``docs/index.md`` (and README.md): mkdocs serves every other page
  at ``<page>/index.html`` and rewrites the paths of Markdown images but not of raw HTML, so a
  raw ``<img src="drawings/x.png">`` on ``fabrication.md`` points at
  ``fabrication/drawings/x.png`` on the site, which does not exist.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_MD_IMG = re.compile(r"!\[[^\]]*\]\(([^)\s]+)")
_HTML_IMG = re.compile(r"<img\s[^>]*src=\"([^\"]+)\"")
_ROOT_PAGES = {ROOT / "README.md", ROOT / "docs" / "index.md"}


def _pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def test_every_image_target_exists():
    missing = []
    for page in _pages():
        text = page.read_text(encoding="utf-8")
        for src in _MD_IMG.findall(text) + _HTML_IMG.findall(text):
            if "://" in src:
                continue
            if not (page.parent / src.split("#")[0]).is_file():
                missing.append(f"{page.relative_to(ROOT)}: {src}")
    assert not missing, "images that do not exist:\n" + "\n".join(missing)


def test_raw_img_only_on_root_pages():
    bad = [f"{p.relative_to(ROOT)}: {src}" for p in _pages() if p not in _ROOT_PAGES
           for src in _HTML_IMG.findall(p.read_text(encoding="utf-8"))]
    assert not bad, ("raw <img> on a page the site serves one folder down (use ![alt](path)"
                     '{ width="N" }):\n' + "\n".join(bad))
