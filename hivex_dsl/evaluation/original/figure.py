"""Our learning curves drawn over the original's mean and band of three runs (matplotlib, the ``plots`` extra): the
figure of `hivex curves -o` and of the baselines and fidelity pages; :mod:`.compare` holds the measure."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .compare import CompareError, RunCurve, as_logged_there, shared_panels
from .curves import OriginalCell
from .evidence import RETURN


def plot(run: RunCurve, cell: OriginalCell, path: Path, panels: Sequence[str] | None = None,
         columns: int = 3, others: Sequence[RunCurve] = ()) -> Path:
    """Draw :func:`figure` into a PNG at ``path``."""
    fig = figure(run, cell, panels, columns, others)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Software": None})
    _close(fig)
    return path


def picture(run: RunCurve, cell: OriginalCell, panels: Sequence[str] | None = None, columns: int = 3,
            others: Sequence[RunCurve] = ()) -> np.ndarray:
    """:func:`figure` as an (H, W, 3) uint8 picture (the docs compare pictures within a tolerance, not bytes)."""
    fig = figure(run, cell, panels, columns, others)
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    _close(fig)
    return pixels


def figure(run: RunCurve, cell: OriginalCell, panels: Sequence[str] | None = None, columns: int = 3,
           others: Sequence[RunCurve] = (), panel_size: tuple[float, float] = (3.6, 2.4), dpi: int = 80) -> Any:
    """Our curve of every shared panel (or ``panels``) over the original's training mean and band (and, on the
    return, our checkpoints on the test seeds), with ``others`` (other training seeds) dashed beside it; one small
    axis a panel. Needs matplotlib (the ``plots`` extra)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise CompareError("the curves' figure needs matplotlib: pip install 'hivex-dsl[plots]'") from None
    names = list(panels) if panels is not None else shared_panels(run, cell)
    if not names:
        raise CompareError(f"the run logs none of the panels of the original's {cell.file}")
    rows = -(-len(names) // columns)
    cols = min(columns, len(names))
    fig, axes = plt.subplots(rows, cols, figsize=(max(panel_size[0] * cols, 5.0), panel_size[1] * rows + 0.4),
                             dpi=dpi, squeeze=False)
    for ax, name in zip(axes.flat, names):
        _draw_panel(ax, run, cell, name, others)
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    axes.flat[0].legend(fontsize=6, loc="best")
    stale = "STALE record, not evidence: " if run.stale or any(o.stale for o in others) else ""
    ours = run.label + (f" (solid), {len(others)} more seed{'s' * (len(others) > 1)} (dashed)" if others else "")
    fig.suptitle(f"{stale}{cell.title}\nred: the original (mean and band of 3 runs), blue: {ours}", fontsize=7,
                 color="tab:red" if stale else "black")
    fig.tight_layout()
    return fig


def _close(fig: Any) -> None:
    import matplotlib.pyplot as plt

    plt.close(fig)


def _draw_panel(ax: Any, run: RunCurve, cell: OriginalCell, name: str, others: Sequence[RunCurve] = ()) -> None:
    training = cell.panels[name].training
    assert training is not None
    ax.fill_between(training.band_steps, training.lower, training.upper, color="tab:red", alpha=0.2, linewidth=0)
    ax.plot(training.steps, training.mean, color="tab:red", linewidth=1, label="original, training")
    values = as_logged_there(name, run.panels[name])
    known = ~np.isnan(values)
    ax.plot(run.steps[known], values[known], color="tab:blue", linewidth=0.8, alpha=0.8,
            marker="o" if known.sum() < 20 else None, markersize=3, label=f"{run.label}, training")
    for other in others:
        if name in other.panels:
            values = as_logged_there(name, other.panels[name])
            known = ~np.isnan(values)
            ax.plot(other.steps[known], values[known], color="tab:blue", linewidth=0.8, alpha=0.5,
                    linestyle="--", label=f"{other.label}, training")
    if name == RETURN and run.test is not None:
        ax.plot(*run.test, "s", color="tab:purple", markersize=3, label="ours, checkpoints on test seeds")
    ax.axvline(training.last_step, color="gray", linewidth=0.6, linestyle=":")
    ax.set_title(name, fontsize=8)
    ax.tick_params(labelsize=6)
    ax.xaxis.get_offset_text().set_fontsize(6)
    ax.grid(alpha=0.3)


__all__ = ["figure", "picture", "plot"]
