"""How the results page writes numbers and tables (``scripts/results_page.py``)."""

from __future__ import annotations

import math




def num(x: float | str) -> float:
    """A stored number (the results files store infinities as the string ``"inf"``)."""
    return float(x)


def pct(x: float, digits: int = 2, sign: bool = False) -> str:
    """``x`` (a ratio) in per cent."""
    return f"{100 * x:{'+' if sign else ''}.{digits}f} %"


def sci(x: float, digits: int = 1) -> str:
    """``x`` in short scientific notation (``1.2e-08`` -> ``1.2e-8``)."""
    mant, exp = f"{x:.{digits}e}".split("e")
    return f"{mant}e{int(exp)}"


def val(x: float | str | None, digits: int = 4) -> str:
    """A stored value, ``unstable`` for an infinite one (a closed loop unstable somewhere in the box), ``-`` for none (an
    evaluation that failed before it)."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return "unstable" if math.isinf(num(x)) else f"{num(x):.{digits}f}"


def cm(h: float, digits: int = 3) -> str:
    """A section side in m, written in cm without trailing zeros beyond ``digits``."""
    return f"{100 * h:.{digits}f}".rstrip("0").rstrip(".")


def table(head: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def ordinal(n: int) -> str:
    return f"{n}{'th' if 10 <= n % 100 <= 20 else {1: 'st', 2: 'nd', 3: 'rd'}.get(n % 10, 'th')}"


def signed(x: float) -> str:
    """A shift in per cent with its sign (``+0.5``, ``-1``, ``0``)."""
    return "0" if x == 0 else f"{x:+g}"


def ok(status: str) -> bool:
    return status == "ok"


def split_stalls(valid: list[dict]) -> tuple[list[dict], list[dict]]:
    """The valid grid points whose J_c is near the others' (within twice their median), and the outliers above them:
    syntheses that stopped on a plateau."""
    jv = sorted(g["J_c"] for g in valid)
    median = jv[len(jv) // 2]
    return [g for g in valid if g["J_c"] <= 2 * median], [g for g in valid if g["J_c"] > 2 * median]


def stalls_text(stalls: list[dict]) -> str:
    return "; ".join(f"{cm(g['h'], 2)} cm: J_c {g['J_c']:.4f}, Z_c {g['Z_c']:.2f}" for g in stalls)


def ranges(values: list[float]) -> str:
    """Contiguous runs of an evenly spaced, sorted list of shifts in per cent (``-1.5 to +0.5 %``)."""
    if not values:
        return "none"
    runs, start, prev = [], values[0], values[0]
    for v in values[1:] + [math.nan]:
        if not (v - prev <= 0.5 + 1e-9):
            runs.append(f"{start:+g} %" if start == prev else f"{start:+g} to {prev:+g} %")
            start = v
        prev = v
    return ", ".join(runs)
