"""Output folders a command may write into: it owns only the files it writes.

A command that takes ``--out DIR`` declares the file names it writes there
(glob patterns). It refuses a folder holding anything else (the folder may be the
user's), so rewriting or resuming never touches a foreign file; it never deletes
a file it did not write. Temporary files of an interrupted atomic write
(``.NAME.*``, see :mod:`cad.io.atomic`) count as the command's own.
"""

from __future__ import annotations

import fnmatch
from pathlib import Path

from cad.errors import DesignError


def check_out_dir(path: str | Path, owned: tuple[str, ...], flag: str = "--out") -> Path:
    """Return ``path`` after checking it is absent, empty or holds only ``owned`` files.

    Raises DesignError naming ``flag`` when ``path`` is a file or holds a foreign entry.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise DesignError(flag, f"{p} is a file, not a folder")
    if not p.exists():
        return p
    patterns = owned + tuple(f".{o}.*" for o in owned)
    foreign = sorted(e.name for e in p.iterdir()
                     if not any(fnmatch.fnmatch(e.name, pat) for pat in patterns) or e.is_dir())
    if foreign:
        shown = ", ".join(foreign[:3]) + (" ..." if len(foreign) > 3 else "")
        raise DesignError(flag, f"{p} holds files this command did not write ({shown}); "
                          "choose an empty or new folder")
    return p
