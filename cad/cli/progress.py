"""Progress of long commands: a rich bar on a terminal, one line per stage otherwise.

``with stages("build") as progress: work(progress=progress)`` -- ``progress(description,
done, total)`` is the callback the build and the sweeps accept. Off a terminal (a pipe, a
log file, CI) each new stage prints ``hapticad: [done/total] description`` on stderr, so
long work is never silent. The run's implausible values (:mod:`cad.design.bounds`) are printed before
the first stage, so a unit slip is seen before minutes of work; its other warnings when the
command ends; a command that fails prints only its error line (with one warning as a note).
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable, Iterator

Progress = Callable[[str, int, int], None]


@contextlib.contextmanager
def stages(title: str, stream=None) -> Iterator[Progress]:
    """A progress callback for the duration of the block (module docstring)."""
    from cad.design import bounds

    stream = stream if stream is not None else sys.stderr
    if stream.isatty():
        from rich.console import Console
        from rich.progress import BarColumn, TextColumn, TimeElapsedColumn
        from rich.progress import Progress as Bar

        with Bar(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
                 transient=True, console=Console(file=stream)) as bar:
            task = bar.add_task(title, total=1)

            def update(desc: str, done: int, total: int) -> None:
                bounds.flush(early=True)  # sys.stderr now: rich prints it above the bar
                bar.update(task, description=desc, completed=done, total=total)

            yield update
        return
    last = [None]

    def line(desc: str, done: int, total: int) -> None:
        if desc != last[0]:
            last[0] = desc
            bounds.flush(stream, early=True)
            print(f"hapticad: [{done}/{total}] {desc}", file=stream, flush=True)

    yield line
