"""The figure commands' files (mpm1d_post.output_files): written under a temporary name and renamed
when complete; a failed write leaves the older file, no temporary file, and an OutputError naming
the file and the system's cause, which a command reports with exit code 3 (test/cli/test_full_disk.py
runs the commands themselves on a full disk)."""
import errno
import os

import pytest

from mpm1d_post.output_files import OUTPUT_ERROR, OutputError, replacing, replacing_path, save_figure_file, \
    with_output_errors, write_text


def test_replacing_writes_the_file_whole(tmp_path):
    path = tmp_path / 'summary.md'
    path.write_text('older')
    write_text(path, 'new text\n')
    assert path.read_text() == 'new text\n'
    assert [p.name for p in tmp_path.iterdir()] == ['summary.md']


@pytest.mark.parametrize('code, words', [(errno.ENOSPC, 'no space left on device'),
                                         (errno.EDQUOT, 'disk quota exceeded'), (errno.EIO, 'input/output error')])
def test_a_failed_write_leaves_the_older_file(tmp_path, code, words):
    path = tmp_path / 'orders.csv'
    path.write_text('older')
    with pytest.raises(OutputError) as caught:
        with replacing(path, 'w') as handle:
            handle.write('part of it')
            raise OSError(code, os.strerror(code))
    assert str(caught.value.strerror) == f"cannot write '{path}': {words}"
    assert path.read_text() == 'older'
    assert [p.name for p in tmp_path.iterdir()] == ['orders.csv']


class FullDiskFigure:
    """A figure whose savefig writes some bytes, then meets a full disk."""

    def savefig(self, handle, **kwargs):
        handle.write(b'\x89PNG partial')
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_figure_on_a_full_disk(tmp_path):
    path = tmp_path / 'error_vs_time.png'
    with pytest.raises(OutputError):
        save_figure_file(FullDiskFigure(), path)
    assert list(tmp_path.iterdir()) == []


def test_a_command_reports_it_with_exit_3(tmp_path, capsys):
    def main(argv):
        save_figure_file(FullDiskFigure(), tmp_path / 'figure.png')
        return 0
    assert with_output_errors('mpm1d-some-figures', main, []) == OUTPUT_ERROR == 3
    assert capsys.readouterr().err == (f"mpm1d-some-figures: cannot write '{tmp_path / 'figure.png'}': "
                                       'no space left on device\n')


def test_a_writer_given_a_path_keeps_the_suffix_and_the_older_file(tmp_path):
    path = tmp_path / 'run.gif'
    path.write_bytes(b'older')
    with pytest.raises(OutputError):
        with replacing_path(path) as temporary:
            assert temporary.suffix == '.gif' and temporary.parent == tmp_path
            temporary.write_bytes(b'GIF89a partial')
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert path.read_bytes() == b'older'
    assert [p.name for p in tmp_path.iterdir()] == ['run.gif']
    with replacing_path(path) as temporary:
        temporary.write_bytes(b'GIF89a whole')
    assert path.read_bytes() == b'GIF89a whole'
    assert [p.name for p in tmp_path.iterdir()] == ['run.gif']
