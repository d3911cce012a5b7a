"""Links between the documentation pages (README.md, docs/*.md): every relative link names a file
that exists and, with a #fragment, a heading or an `<a id>` of that page (GitHub's anchors)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / 'README.md', *sorted((ROOT / 'docs').glob('*.md'))]
#: [text](target) and ![alt](target), the target without a title; code spans and blocks are removed first.
LINK = re.compile(r'!?\[[^\]]*\]\(((?:[^()\s]|\([^()\s]*\))+)\)')


def prose(text: str) -> str:
    """The page without fenced code blocks and code spans (their brackets are not links)."""
    text = re.sub(r'^```.*?^```', '', text, flags=re.S | re.M)
    return re.sub(r'`[^`\n]*`', '', text)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation but '-' and '_' dropped, spaces to '-'."""
    text = re.sub(r'`', '', heading.strip().lower())
    text = re.sub(r'[^\w\- ]', '', text)
    return text.replace(' ', '-')


def anchors(page: Path) -> set:
    text = page.read_text(encoding='utf-8')
    found, seen = set(), {}
    for line in re.sub(r'^```.*?^```', '', text, flags=re.S | re.M).splitlines():
        heading = re.match(r'#{1,6} (.+)', line)
        if heading:
            base = slug(heading.group(1))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else f'{base}-{count}')
    found |= set(re.findall(r'<a id="([^"]+)"', text))
    return found


def links(page: Path):
    for target in LINK.findall(prose(page.read_text(encoding='utf-8'))):
        if re.match(r'[a-z]+:', target):
            continue
        yield target


@pytest.mark.parametrize('page', PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(page):
    broken = []
    for target in links(page):
        path, _, fragment = target.partition('#')
        goal = (page.parent / path).resolve() if path else page
        if not goal.exists():
            broken.append(f'{target} (no file {goal.relative_to(ROOT) if goal.is_relative_to(ROOT) else goal})')
        elif fragment and goal.suffix == '.md' and fragment not in anchors(goal):
            broken.append(f'{target} (no heading or <a id> "{fragment}" in {goal.relative_to(ROOT)})')
    assert not broken, f'{page.relative_to(ROOT)}: broken links: ' + '; '.join(broken)


def test_slugs_follow_github():
    """The anchors GitHub makes of this project's kinds of headings."""
    assert slug('Shape functions and transfers (`&discretisation shape=, transfer=`)') == \
        'shape-functions-and-transfers-discretisation-shape-transfer'
    assert slug('Shapes and transfers (`studies/shapes`)') == 'shapes-and-transfers-studiesshapes'
    assert slug("`kind='column'`: a column under its own weight, suddenly loaded") == \
        'kindcolumn-a-column-under-its-own-weight-suddenly-loaded'
    assert slug('&scene') == 'scene'
    assert slug('Quick start (fresh Debian/Ubuntu machine)') == 'quick-start-fresh-debianubuntu-machine'


def test_a_broken_link_is_found(tmp_path):
    """The check sees a missing file and a missing heading (so that a pass means something)."""
    page = tmp_path / 'page.md'
    (tmp_path / 'other.md').write_text('# Title\n\n## A section\n<a id="entry"></a>\n')
    page.write_text('[ok](other.md#a-section) [ok](other.md#entry) [bad](other.md#nothing) [bad](gone.md) '
                    '`[code](gone.md)`\n```\n[block](gone.md)\n```\n[doi](https://doi.org/10.1016/0045-7825(94)90112-0)\n')
    targets = list(links(page))
    assert targets == ['other.md#a-section', 'other.md#entry', 'other.md#nothing', 'gone.md']
    assert LINK.findall('[doi](https://doi.org/10.1016/0045-7825(94)90112-0)') == \
        ['https://doi.org/10.1016/0045-7825(94)90112-0']
    assert anchors(tmp_path / 'other.md') == {'title', 'a-section', 'entry'}
