"""LICENSE and CITATION.cff against fpm.toml and the reference list of docs/theory.md."""
from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOI = re.compile(r'10\.\d{4,9}/[^\s"\]]+?(?=[)"\]]?(?:\s|$))')


def manifest() -> dict:
    with open(ROOT / 'fpm.toml', 'rb') as handle:
        return tomllib.load(handle)


def citation_text() -> str:
    return (ROOT / 'CITATION.cff').read_text(encoding='utf-8')


def citation_field(name: str) -> str:
    found = re.search(rf'^{name}:\s*"?([^"\n]+)"?\s*$', citation_text(), re.M)
    assert found, f'CITATION.cff has no top-level {name}'
    return found.group(1)


def theory_references() -> str:
    text = (ROOT / 'docs' / 'theory.md').read_text(encoding='utf-8')
    return text[text.index('\n## References'):]


def test_citation_version_and_license_are_the_manifests():
    """CITATION.cff names fpm.toml's version and licence, and LICENSE is that licence's text."""
    fpm = manifest()
    assert citation_field('version') == fpm['version'], 'set version in CITATION.cff to fpm.toml\'s'
    assert citation_field('license') == fpm['license']
    assert fpm['license'] == 'MIT'
    license_text = (ROOT / 'LICENSE').read_text(encoding='utf-8')
    assert license_text.startswith('MIT License') and f"Copyright (c) 2026 {fpm['author']}" in license_text
    assert 'THE SOFTWARE IS PROVIDED "AS IS"' in license_text


def dois(text: str) -> set:
    return {d.rstrip('.,;').lower() for d in DOI.findall(text)}


def test_citation_references_are_the_theory_pages_list():
    """Every DOI of CITATION.cff's references is in docs/theory.md's list, and the reverse."""
    in_citation = dois(citation_text())
    in_theory = dois(theory_references())
    assert len(in_citation) >= 10
    assert in_citation == in_theory, (f'only in CITATION.cff: {sorted(in_citation - in_theory)}; '
                                      f'only in docs/theory.md: {sorted(in_theory - in_citation)}')


def test_doi_pattern_reads_the_forms_used():
    """The DOI pattern takes DOIs with brackets and dots whole, in YAML quotes and Markdown links."""
    text = ('doi: "10.1016/0045-7825(94)90112-0"\n'
            '[doi:10.1016/S0045-7825(99)00338-2](https://doi.org/10.1016/S0045-7825(99)00338-2) — x\n'
            '[doi:10.1002/nme.2360](https://doi.org/10.1002/nme.2360)\n')
    assert dois(text) == {'10.1016/0045-7825(94)90112-0', '10.1016/s0045-7825(99)00338-2', '10.1002/nme.2360'}


def test_citation_file_is_valid_cff():
    """CITATION.cff validates against the CFF 1.2.0 schema (cffconvert; skipped where it is not installed)."""
    cffconvert = pytest.importorskip('cffconvert')
    cffconvert.Citation(citation_text()).validate()
