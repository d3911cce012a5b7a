"""Markdown tables of the summaries, written once: a header, its separator and one line per row, and
the text of a number that may not exist (NaN: no result).

    >>> markdown_table(['scheme', 'order'], [['usl', number(2.01, '.2f')], ['usf', number(float('nan'), '.2f')]])
    ['| scheme | order |', '|---|---|', '| usl | 2.01 |', '| usf | nan |']
"""
from __future__ import annotations

import math
from typing import Iterable, List, Optional, Sequence


def table_row(cells: Sequence[object]) -> str:
    """'| a | b |' from the cells (each written with str())."""
    return '| ' + ' | '.join(str(cell) for cell in cells) + ' |'


def markdown_table(header: Sequence[object], rows: Iterable[Sequence[object]] = ()) -> List[str]:
    """The lines of a markdown table: the header, the separator, one line per row. Every row has the
    header's number of cells (a ValueError names the row that has not)."""
    lines = [table_row(header), '|' + '---|' * len(header)]
    for row in rows:
        if len(row) != len(header):
            raise ValueError(f'markdown_table: a row of {len(row)} cells under a header of {len(header)}: {list(row)!r}')
        lines.append(table_row(row))
    return lines


def number(value: Optional[float], spec: str = '.3g', missing: str = 'nan') -> str:
    """`value` formatted with `spec` (format(value, spec)), or `missing` where there is no number (None,
    NaN or infinite)."""
    if value is None or not math.isfinite(float(value)):
        return missing
    return format(value, spec)
