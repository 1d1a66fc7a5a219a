"""The ``hapticad`` typer application and its error boundary.

Exit codes: 0 success, 1 a target missed (``check``), 2 bad input (one line on
stderr naming the field and the reason, never a traceback), 130 / 143 interrupted by
SIGINT / SIGTERM (``hapticad: aborted``, nothing published: :mod:`cad.io.signals`).
"""

from __future__ import annotations

import importlib
import pkgutil
import re
import sys
import unicodedata

import typer

from cad.errors import HapticadError, TargetMissed

app = typer.Typer(
    name="hapticad",
    help="Parametric CAD generator for haptic-device hardware.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"max_content_width": 120},  # help texts are plain: "[parts]" is a TOML table, not a style tag
)


_REGISTERED = False


def _version(value: bool) -> None:
    if value:
        from cad import __version__

        print(f"hapticad {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", help="Print the version and exit.", callback=_version, is_eager=True
    ),
) -> None:
    """Parametric CAD generator for haptic-device hardware."""


def register_commands() -> None:
    global _REGISTERED
    if _REGISTERED:
        return
    _REGISTERED = True
    import cad.cli as pkg

    for mod in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
        if mod.name.startswith("cmd_"):
            importlib.import_module(f"cad.cli.{mod.name}").register(app)


def fail(message: str, code: int = 2) -> typer.Exit:
    """Print ``hapticad: error: <message>`` on stderr and return the Exit to raise.

    With ``code`` 2 the line carries the likely unit slip (:func:`_error`).
    """
    if code == 2:
        _error(message)
    else:
        _print_line(f"hapticad: error: {message}")
    return typer.Exit(code)


#: An error line longer than this (characters) is cut in its middle, and any one word (a
#: value without spaces: a name, a path) longer than :data:`WORD_MAX_CHARS` too: a
#: megabyte-long name or a million-element list echoed whole buries the reason (issue 22 §5).
LINE_MAX_CHARS = 1500
WORD_MAX_CHARS = 240


def _cut(text: str, keep: int) -> str:
    """``text`` with its middle replaced by ``...[N characters cut]...`` when longer than ``keep``."""
    if len(text) <= keep:
        return text
    head, tail = keep * 2 // 3, keep // 3
    return f"{text[:head]}...[{len(text) - head - tail} characters cut]...{text[len(text) - tail:]}"


def _visible(line: str) -> str:
    """``line`` with every control character (C0, DEL, C1: ESC, BEL, NUL ...) shown as its
    Python escape, so an error quoting a design's key or a file's cell never drives the
    terminal (an OSC 52 clipboard write, a screen clear)."""
    return "".join(repr(c)[1:-1] if unicodedata.category(c) == "Cc" else c for c in line)


def readable(line: str) -> str:
    """``line`` cut to a readable length: every word (run without spaces) to
    :data:`WORD_MAX_CHARS`, the whole to :data:`LINE_MAX_CHARS`, keeping both ends (the
    field comes first, the reason and the fix last); one line (newlines become spaces)."""
    line = _visible(" ".join(line.splitlines()))
    if len(line) <= WORD_MAX_CHARS:
        return line
    long_word = re.compile(r"\S{" + str(WORD_MAX_CHARS + 1) + ",}")
    line = long_word.sub(lambda m: _cut(m.group(0), WORD_MAX_CHARS), line)
    return _cut(line, LINE_MAX_CHARS)


def _print_line(line: str) -> None:
    """Print one ``hapticad: ...`` line on stderr, cut to a readable length (:func:`readable`):
    the one place every error line of the CLI is written."""
    print(readable(line), file=sys.stderr)


def _error(message: str, field: str | None = None) -> None:
    """The one stderr line of exit 2: the error and, in it, the hint of this run's
    implausible-value warning (:func:`cad.design.bounds.error_line`); no warning lines."""
    from cad.design import bounds

    _print_line(f"hapticad: error: {bounds.error_line(message, field)}")


def print_json(obj: dict, **dumps_kwargs) -> None:
    """Print one JSON object on stdout with the run's ``warnings`` list added (every ``--json``).

    ``warnings`` holds every implausible value (:mod:`cad.design.bounds`) and every data
    warning (e.g. an STL that is not watertight) of this command, as printed on stderr.
    """
    import json

    from cad.design import bounds

    print(json.dumps({**obj, "warnings": bounds.collected()}, **dumps_kwargs))


def _dedupe_sentences(msg: str) -> str:
    """Drop a sentence repeated verbatim (click and typer both append "Did you mean ...?")."""
    out: list[str] = []
    for part in msg.replace("? ", "?\n").replace(". ", ".\n").split("\n"):
        if part not in out:
            out.append(part)
    return " ".join(out)


def run(argv: list[str] | None = None) -> int:
    """Run the CLI on ``argv`` and return the exit code (tests call this in-process).

    0 success, 1 a target missed, 2 bad input (one line on stderr, no traceback).
    Warnings (implausible values) are printed on stderr unless the exit code is 2; then the
    error line carries their unit-slip hint instead (:func:`cad.design.bounds.error_line`).
    """
    from cad.design import bounds
    from cad.io import cache_faults

    bounds.reset()
    cache_faults.reset()  # a cache write fault is said once per command
    code = _run(argv)
    if code != 2:
        bounds.flush()
    return code


def _run(argv: list[str] | None) -> int:
    if not _REGISTERED:
        register_commands()
    try:
        return _run_app(argv)
    finally:
        handle = sys.modules.get("cad.parts.handle")  # per-command script opt-in ends here
        if handle is not None:
            handle.clear_script_policy()


def _run_app(argv: list[str] | None) -> int:
    click_error = next(c for c in typer.BadParameter.__mro__ if c.__name__ == "ClickException")
    try:
        rv = app(args=argv, prog_name="hapticad", standalone_mode=False)
        if rv == 130:  # typer turns KeyboardInterrupt into a silent Exit(130), click returns it
            return _aborted()
        return rv if isinstance(rv, int) else 0
    except typer.Exit as exc:
        if int(exc.exit_code) == 130:
            return _aborted()
        return int(exc.exit_code)
    except (typer.Abort, KeyboardInterrupt):
        return _aborted()
    except click_error as exc:  # usage errors: one line, exit 2
        if type(exc).__name__ == "NoArgsIsHelpError":  # bare `hapticad`: the help, exit 0
            print(exc.ctx.get_help() if exc.ctx else "")
            return 0
        msg = _dedupe_sentences(" ".join(exc.format_message().split()))
        _print_line(f"hapticad: error: {msg} (see hapticad --help)")
        return int(getattr(exc, "exit_code", 2))
    except TargetMissed as exc:
        _print_line(f"hapticad: {exc}")
        return 1
    except HapticadError as exc:
        _error(str(exc), getattr(exc, "field", None))
        return 2
    except (OSError, UnicodeDecodeError) as exc:
        _error(str(exc))
        return 2


def _aborted() -> int:
    """``hapticad: aborted`` on stderr, the last line: the warnings recorded so far are printed
    before it (not after, by :func:`run`); the exit code 128 + signal (130 for Ctrl-C)."""
    from cad.design import bounds
    from cad.io import signals

    bounds.flush()
    print("hapticad: aborted", file=sys.stderr, flush=True)
    return signals.exit_code()


def main() -> None:
    """Console-script entry point: SIGINT/SIGTERM abort cleanly (:mod:`cad.io.signals`)."""
    from cad.io import signals

    signals.install()
    try:
        code = run()
        signals.finish()  # the command is over: a later signal cannot kill the process
    except BaseException:
        signals.finish()
        if signals.received() is None or signals.committed():
            raise
        code = _aborted()  # e.g. an ImportError raised by a library interrupted mid-import
    if signals.received() is not None and code != signals.exit_code() and not signals.committed():
        code = _aborted()  # a library swallowed the interrupt: nothing was published
    if signals.received() is not None:
        signals.exit_now(code)
    sys.exit(code)


if __name__ == "__main__":
    main()
