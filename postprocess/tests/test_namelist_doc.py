"""docs/namelist.md against the parameter registry of the built mpm1d (`mpm1d --list-parameters`).

The page is generated (``python -m mpm1d_post.namelist_doc``); these tests regenerate it and fail,
naming the difference and the command that fixes it, when the committed page is stale.
"""
from __future__ import annotations

import dataclasses
import re
import subprocess
from pathlib import Path

import pytest

from mpm1d_post import namelist_doc
from mpm1d_post.loader import Parameter, load_run, load_sweep

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / 'docs' / 'namelist.md'


@pytest.fixture(scope='module')
def registry(mpm1d):
    return namelist_doc.registry_from_program(str(mpm1d))


def page_text() -> str:
    return PAGE.read_text(encoding='utf-8')


def test_page_is_generated_from_the_registry(mpm1d, registry):
    """docs/namelist.md is exactly what the generator makes of the built mpm1d's registry."""
    expected = namelist_doc.render(registry, used=namelist_doc.used_by_built_in_case(str(mpm1d)))
    committed = page_text()
    if committed != expected:
        pytest.fail(f'docs/namelist.md is stale (it differs from `mpm1d --list-parameters`); regenerate it in '
                    f'the repository with\n    {namelist_doc.COMMAND}\n{namelist_doc.difference(committed, expected)}',
                    pytrace=False)


def documented_rows(text: str) -> set:
    """(group, variable) of every table row under a `## &group` heading."""
    rows, group = set(), None
    for line in text.splitlines():
        heading = re.match(r'## &(\w+)', line)
        if heading:
            group = heading.group(1)
        row = re.match(r'\| `(\w+)` \|', line)
        if row and group:
            rows.add((group, row.group(1)))
    return rows


def test_every_listed_variable_has_a_row(registry):
    """Every registry variable has a row in its group's table (and the page no row the registry lacks)."""
    rows = documented_rows(page_text())
    listed = {(p.group, p.name) for p in registry}
    assert {'scene', 'discretisation', 'run', 'output', 'guards', 'sweep'} <= {g for g, _ in listed}
    missing = sorted(f'{g}.{n}' for g, n in listed - rows)
    extra = sorted(f'{g}.{n}' for g, n in rows - listed)
    assert not missing and not extra, (f'docs/namelist.md lacks {missing}, documents unknown {extra}; '
                                       f'regenerate it: {namelist_doc.COMMAND}')


def fortran_block(text: str) -> str:
    return re.search(r'```fortran\n(.*?)```', text, re.S).group(1)


def test_example_namelist_is_the_built_in_case(mpm1d, tmp_path):
    """The page's example ("every group at its defaults") is accepted and runs exactly the case mpm1d
    runs without input: the same summary, bit for bit."""
    example = fortran_block(page_text())
    assert {m for m in re.findall(r'^&(\w+)', example, re.M)} == set(namelist_doc.RUN_GROUPS)
    (tmp_path / 'example').mkdir()
    (tmp_path / 'builtin').mkdir()
    (tmp_path / 'example' / 'example.nml').write_text(example)
    for folder, args in (('example', ['example.nml']), ('builtin', [])):
        done = subprocess.run([str(mpm1d), *args, '--quiet'], cwd=tmp_path / folder, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
    ran, builtin = (load_run(str(tmp_path / f / 'bar.h5')) for f in ('example', 'builtin'))
    for name in ('max_error', 'relative_error', 'steps', 'particles', 'dt', 'final_energy'):
        assert ran.summary[name] == builtin.summary[name], name
    assert ran.config['namelist'] == builtin.config['namelist']


def test_sweep_example_gives_the_cases_it_says(mpm1d, tmp_path):
    """The page's &sweep example is accepted and gives the six cases it announces."""
    text = page_text()
    sweep = re.search(r'`(&sweep [^`]*)` \((\w+) cases, no timing pass\)', text)
    assert sweep, 'the page has no &sweep example'
    (tmp_path / 'sweep.nml').write_text(f"&output file='sweep.h5' /\n{sweep.group(1)}\n")
    done = subprocess.run([str(mpm1d), 'sweep.nml', '--quiet', 'run.periods=0.1'], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    loaded = load_sweep(str(tmp_path / 'sweep.h5'))
    words = {'six': 6}
    assert len(loaded.cases['max_error']) == words[sweep.group(2)]
    assert float(loaded.sweep[0]['min_time']) == 0.0


def test_files_store_the_listed_registry(mpm1d, registry, tmp_path):
    """/config/parameters of an output file holds the registry as --list-parameters prints it, those
    entries its scene kind uses (the values are the run's: here periods); another kind's are not there."""
    subprocess.run([str(mpm1d), '--quiet', 'run.periods=0.5'], cwd=tmp_path, check=True, capture_output=True)
    stored = load_run(str(tmp_path / 'bar.h5')).parameters
    listed = [p for p in registry if p.group != 'sweep' and _used_by(p, 'vibrating_bar')]
    assert [dataclasses.replace(p, value='') for p in stored] == [dataclasses.replace(p, value='') for p in listed]
    assert [p.value for p in stored if p.name == 'periods'] == ['0.50000000000000000']
    assert {p.name: p.kinds for p in stored}['mode'] == 'vibrating_bar'
    assert 'gravity' not in {p.name for p in stored} and 'gravity' in {p.name for p in registry}


def _used_by(p, kind):
    """Is registry entry `p` a variable of scene kind `kind` (its kinds column empty: of every kind)?"""
    return not p.kinds or kind in [k.strip() for k in p.kinds.split(',')]


def test_check_mode_names_a_stale_page_and_the_fix(mpm1d, registry, tmp_path, capsys):
    """--check exits 1 on a stale page, printing the difference and the command; writing fixes it."""
    page = tmp_path / 'namelist.md'
    fresh = namelist_doc.render(registry, used=namelist_doc.used_by_built_in_case(str(mpm1d)))
    stale = fresh.replace('| `elements` | integer | 20 |', '| `elements` | integer | 40 |')
    assert stale != fresh
    page.write_text(stale, encoding='utf-8')
    assert namelist_doc.main(['--mpm1d', str(mpm1d), '-o', str(page), '--check']) == 1
    err = capsys.readouterr().err
    assert namelist_doc.COMMAND in err and '-| `elements` | integer | 40 |' in err
    assert namelist_doc.main(['--mpm1d', str(mpm1d), '-o', str(page)]) == 0
    assert namelist_doc.main(['--mpm1d', str(mpm1d), '-o', str(page), '--check']) == 0
    assert page.read_text(encoding='utf-8') == fresh
    assert namelist_doc.main(['--mpm1d', str(tmp_path / 'no_such_mpm1d'), '-o', str(page)]) == 2


@pytest.mark.parametrize('text, shown, literal', [
    ('0.10000000000000001', '0.1', '0.1'), ('7800.0000000000000', '7800', '7800.0'),
    ('200000000000.00000', '2e11', '2.0e11'), ('0.25000000000000001E-1', '0.025', '0.025'),
    ('-1.0000000000000000', '-1', '-1.0'), ('0.0000000000000000', '0', '0.0'),
    ('1.5E-300', '1.5e-300', '1.5e-300'),
    ('0.33333333333333331', '0.3333333333333333', '0.3333333333333333'), ('1.0E6', '1e6', '1.0e6')])
def test_defaults_are_shown_short_and_read_back_exactly(text, shown, literal):
    """A default is shown in its shortest form that reads back as the same double."""
    assert namelist_doc.shortest(text) == shown
    assert namelist_doc.fortran_real(text) == literal
    assert float(shown) == float(literal) == float(text)


def test_a_group_without_template_text_is_refused():
    """A new registry group stops the generator until the template describes it."""
    p = Parameter(group='contact_law', name='law', attribute='law', type='text', unit='', value="'hencky'",
                  allowed="'hencky'", sweep_list='', help='the law')
    with pytest.raises(ValueError, match='contact_law'):
        namelist_doc.render([p])


def test_table_cells_cannot_break_a_row():
    """A '|' or '*' in the registry's text is escaped, so the row keeps its columns."""
    p = Parameter(group='run', name='x', attribute='y', type='real', unit='m', value='1.0', allowed='a | b',
                  sweep_list='x', help='2 * 3', sweep_alias='xs', kinds='')
    row = [line for line in namelist_doc.group_table([p]) if line.startswith('| `x`')][0]
    assert len(re.split(r'(?<!\\)\|', row)) == len(namelist_doc.group_table([p])[0].split('|'))
    assert '2 \\* 3 (`/config` attribute `y`)' in row and '`x` (former `xs`)' in row
