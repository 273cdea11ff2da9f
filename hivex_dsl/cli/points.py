"""One point of a sweep file, chosen on the command line: ``--point 3`` (its index, as `hivex compile` numbers
the points) or ``--point task=1,pattern=2`` (its swept values). Shared by `hivex run`, `render` and `evaluate`."""

from __future__ import annotations

import re
from typing import Any, Optional, Sequence

from ..base.errors import HivexError, did_you_mean


# an index as the command line writes it: ASCII digits only (str.isdigit also takes '²', '١' and '３')
INDEX = re.compile(r"[0-9]+")


def one_point(source: Any, selector: Optional[str]) -> Any:
    """The compiled scenario of ``source`` that ``selector`` names; a file without a sweep is its one scenario
    (a selector other than 0 is refused). Without a selector a sweep is refused, with how to choose."""
    from ..compiler import compile_all

    points = compile_all(source)
    if selector is None:
        if len(points) == 1:
            return points[0]
        raise HivexError(f"{source} sweeps over {len(points)} points: choose one with --point INDEX (0 to "
                         f"{len(points) - 1}) or --point {_example(points[0].sweep_point)}; `hivex compile {source}` "
                         "lists them")
    return select(points, selector, str(source))


def select(points: Sequence[Any], selector: str, source: str) -> Any:
    """The point ``selector`` names among ``points`` (see the module)."""
    text = selector.strip()
    if INDEX.fullmatch(text):
        index = int(text)
        if index >= len(points):
            raise HivexError(f"--point {selector}: {source} has {len(points)} point{'s' * (len(points) != 1)} "
                             f"(0 to {len(points) - 1})")
        return points[index]
    wanted = dict(_pair(item, selector) for item in text.split(","))
    swept = list(points[0].sweep_point)
    for key in wanted:
        if key not in swept:
            raise HivexError(f"--point {selector}: {source} does not sweep {key!r}{did_you_mean(key, swept)}; it sweeps "
                             f"{', '.join(swept) if swept else 'nothing'}")
    found = [p for p in points if all(str(p.sweep_point[k]) == v for k, v in wanted.items())]
    if len(found) != 1:
        named = f"{len(found)} points" if found else "no point"
        raise HivexError(f"--point {selector}: {named} of {source} match; give every swept value ({', '.join(swept)}) "
                         "or the point's index")
    return found[0]


def point_indices(selector: str, count: int, source: str) -> list[int]:
    """The indices ``selector`` names among a sweep's ``count`` points: ``"14-29"``, ``"3,5"`` or both
    (``"0,14-16"``), inclusive, as `hivex compile` numbers the points; -> sorted, each once."""
    chosen: set[int] = set()
    for item in selector.split(","):
        first, dash, last = item.strip().partition("-")
        if not INDEX.fullmatch(first) or (dash and not INDEX.fullmatch(last)):
            raise HivexError(f"--points {selector}: expected indices and ranges joined by commas (e.g. 0,14-29), "
                             f"got {item.strip()!r} (indices are written in the digits 0-9)")
        low, high = int(first), int(last) if dash else int(first)
        if low > high:
            raise HivexError(f"--points {selector}: {item.strip()!r} is a range from high to low: write it {high}-{low}")
        if high >= count:
            raise HivexError(f"--points {selector}: {item.strip()!r} is not within the {count} point"
                             f"{'s' * (count != 1)} of {source} (0 to {count - 1})")
        chosen.update(range(low, high + 1))
    return sorted(chosen)


def _pair(item: str, selector: str) -> tuple[str, str]:
    key, sep, value = item.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise HivexError(f"--point {selector}: expected an index or key=value pairs joined by commas, got {item!r}")
    return key.strip(), value.strip()


def _example(point: dict) -> str:
    return ",".join(f"{k}={v}" for k, v in point.items()) or "KEY=VALUE"
