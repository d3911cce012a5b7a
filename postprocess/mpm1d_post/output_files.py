"""Files the figure commands write, as mpm1d writes its own: under a temporary name beside the final
one, renamed to it only when complete. A write that fails (a full disk, a quota, an I/O error, a
file-size limit) leaves nothing under the final name, an older file of that name as it was and no
temporary file, and raises `OutputError` naming the file and the system's cause; each command reports
it with exit code 3, mpm1d's "output could not be written".
"""
import contextlib
import os
import sys
from pathlib import Path
from typing import Callable, Iterator, IO, Optional, Sequence, Union

#: the exit code of a command whose output could not be written (as mpm1d's)
OUTPUT_ERROR = 3

PathLike = Union[str, 'os.PathLike[str]']


class OutputError(OSError):
    """A file could not be written: its path and the system's cause ("no space left on device")."""


def cause(exc: OSError) -> str:
    """The system's words for `exc`, as a cause after a colon ("no space left on device")."""
    text = exc.strerror or str(exc)
    return text[:1].lower() + text[1:] if text[1:2].islower() else text


@contextlib.contextmanager
def replacing(path: PathLike, mode: str = 'w', **kwargs) -> Iterator[IO]:
    """A file opened for writing that replaces `path` when the block ends without an error (open's
    `mode` and keyword arguments); on any error the temporary file is removed and `path` left alone."""
    path = Path(path)
    temporary = path.with_name(f'{path.name}.{os.getpid()}.part')
    try:
        with open(temporary, mode, **kwargs) as handle:
            yield handle
        os.replace(temporary, path)
    except OSError as exc:
        _remove(temporary)
        if isinstance(exc, OutputError):
            raise
        raise OutputError(exc.errno, f"cannot write '{path}': {cause(exc)}") from exc
    except BaseException:
        _remove(temporary)
        raise


@contextlib.contextmanager
def replacing_path(path: PathLike) -> Iterator[Path]:
    """A temporary path beside `path`, with its suffix (for a writer that picks its format by the
    name), that replaces `path` when the block ends without an error; on any error it is removed and
    `path` left alone."""
    path = Path(path)
    temporary = path.with_name(f'{path.stem}.{os.getpid()}.part{path.suffix}')
    try:
        yield temporary
        os.replace(temporary, path)
    except OSError as exc:
        _remove(temporary)
        if isinstance(exc, OutputError):
            raise
        raise OutputError(exc.errno, f"cannot write '{path}': {cause(exc)}") from exc
    except BaseException:
        _remove(temporary)
        raise


def write_text(path: PathLike, text: str) -> None:
    """`text` into `path` (UTF-8), through a temporary file."""
    with replacing(path, 'w', encoding='utf-8') as handle:
        handle.write(text)


def save_figure_file(fig, path: PathLike, **kwargs) -> None:
    """fig.savefig into `path` (the format its suffix names), through a temporary file."""
    path = Path(path)
    with replacing(path, 'wb') as handle:
        fig.savefig(handle, format=path.suffix.lstrip('.') or 'png', **kwargs)


def with_output_errors(program: str, main: Callable[[Optional[Sequence[str]]], int],
                       argv: Optional[Sequence[str]] = None) -> int:
    """`main(argv)`, a file it could not write reported as `program: cannot write 'FILE': CAUSE` on
    standard error with exit code 3."""
    try:
        return main(argv)
    except OutputError as exc:
        print(f'{program}: {exc.strerror}', file=sys.stderr)
        return OUTPUT_ERROR


def _remove(path: Path) -> None:
    try:
        path.unlink()
    except FileNotFoundError:
        pass
