"""Layer 10, docsgen: docs/ generated from the live code with jinja2: nothing in it is written by hand.

Tables come from the registry, the reward tables, the term contracts, the params models, the
real spaces of a compiled default scenario and the bundled scenario files. ``docs/.generated``
lists every file this generator owns, so files it no longer produces can be removed safely.
Imports: every layer below it (base, lang, sim, compiler, runtime, envs through the registry, adapters,
evaluation, train); only the CLI imports docsgen.
"""

from __future__ import annotations

import io
from pathlib import Path, PurePosixPath
from typing import Union

import numpy as np
from jinja2 import Environment, FileSystemLoader, StrictUndefined

from ..compiler import registry
from .adding import PAGE as ADDING_PAGE, adding_context, has_example
from .baselines import PAGE as BASELINES_PAGE, baseline_images, baselines_context, baselines_dir
from .context import environment_context, index_context, language_context, performance_context
from .curves import curve_comparisons, grid_comparisons
from .fidelity_page import fidelity_context
from .figures import preview_figures
from .pages import SCHEMA_FILE, env_page
from .schema import scenario_json_schema, schema_text

MANIFEST = ".generated"
# Pictures are compared by pixels, not bytes: PNG encoders of different zlib builds may differ.
PIXEL_TOLERANCE = 2
Content = Union[str, bytes, np.ndarray]
TEMPLATES = Path(__file__).resolve().parent / "templates"


def md(value: object) -> str:
    """Prose safe in Markdown: ``<name>`` outside code spans is escaped so it is not read as HTML."""
    parts = str(value).split("`")
    return "`".join(part.replace("<", "&lt;") if i % 2 == 0 else part for i, part in enumerate(parts))


def cell(value: object) -> str:
    """Text safe inside one Markdown table cell: one line, pipes escaped."""
    return md(" ".join(str(value).split())).replace("|", "\\|")


def words(names: list[str]) -> str:
    """A list in prose: ``["WRM", "OPC", "DBR"]`` -> ``"WRM, OPC and DBR"``."""
    return " and ".join([", ".join(names[:-1]), names[-1]]) if len(names) > 1 else "".join(names)


def _jinja() -> Environment:
    env = Environment(loader=FileSystemLoader(TEMPLATES), undefined=StrictUndefined, keep_trailing_newline=True,
                      autoescape=False, trim_blocks=True, lstrip_blocks=True)
    env.filters["cell"] = cell
    env.filters["md"] = md
    env.filters["words"] = words
    return env


def render_docs(results: Path | None = None, fidelity: Path | None = None,
                baselines: Path | None = None, tests: Path | None = None,
                overhead: Path | None = None) -> dict[str, Content]:
    """Relative path under docs/ -> file content (text, bytes, or an (H, W, 3) uint8 picture saved as PNG).

    ``results`` is a `hivex bench --json` report; when the file exists, performance.md shows it.
    ``fidelity`` is the stored `hivex audit --suite` report fidelity.md shows (see hivex_dsl.evaluation.fidelity).
    ``baselines`` is the folder of committed baselines (benchmarks/baselines); baselines.md shows them.
    ``tests`` (the checkout's tests/) and ``overhead`` (benchmarks/results/ecosystem.json) feed ecosystem.md's
    library x environment table and its overhead table; the example environment in ``tests`` feeds
    adding_an_environment.md.
    """
    jinja = _jinja()
    has_baselines = baselines is not None and Path(baselines).is_dir()
    docs: dict[str, str | bytes] = {
        "index.md": jinja.get_template("index.md.j2").render(
            **index_context(), has_performance=results is not None and Path(results).is_file(),
            has_baselines=has_baselines),
        "language.md": jinja.get_template("language.md.j2").render(**language_context()),
        SCHEMA_FILE: schema_text(),
    }
    from .ecosystem import ecosystem_context

    docs["ecosystem.md"] = jinja.get_template("ecosystem.md.j2").render(**ecosystem_context(tests, overhead))
    if has_example(tests):
        docs[ADDING_PAGE] = jinja.get_template("adding_an_environment.md.j2").render(**adding_context(tests))
    figures = preview_figures()
    docs["generators.md"] = jinja.get_template("generators.md.j2").render(
        figures=[{"path": rel, "caption": caption} for rel, (caption, _) in figures.items()])
    docs |= {rel: image for rel, (_, image) in figures.items()}
    if results is not None and Path(results).is_file():
        docs["performance.md"] = jinja.get_template("performance.md.j2").render(**performance_context(results))
    comparisons, curve_images = curve_comparisons(baselines if has_baselines else None)
    docs["fidelity.md"] = jinja.get_template("fidelity.md.j2").render(
        **fidelity_context(fidelity or Path("-")), comparisons=comparisons,
        grids=grid_comparisons(baselines if has_baselines else None))
    from .replay_page import PAGE as REPLAY_PAGE, replay_context

    docs[REPLAY_PAGE] = jinja.get_template("replay.md.j2").render(**replay_context())
    if has_baselines:
        docs[BASELINES_PAGE] = jinja.get_template("baselines.md.j2").render(
            **baselines_context(baselines, comparisons))
        docs |= baseline_images(baselines) | curve_images
    page = jinja.get_template("environment.md.j2")
    for env_id, entry in registry.environments().items():
        docs[env_page(env_id)] = page.render(**environment_context(entry))
    return dict(sorted(docs.items()))


def _bytes(content: Content) -> bytes:
    if isinstance(content, np.ndarray):
        from PIL import Image

        buffer = io.BytesIO()
        Image.fromarray(content).save(buffer, format="PNG", optimize=False)
        return buffer.getvalue()
    return content.encode("utf-8") if isinstance(content, str) else content


def _is_fresh(path: Path, content: Content) -> bool:
    if not path.is_file():
        return False
    if not isinstance(content, np.ndarray):
        return path.read_bytes() == _bytes(content)
    from PIL import Image

    try:
        with Image.open(path) as image:
            pixels = np.asarray(image.convert("RGB"))
    except OSError:
        return False
    return pixels.shape == content.shape and int(np.abs(pixels.astype(int) - content).max()) <= PIXEL_TOLERANCE


def _manifest_text(paths: list[str]) -> str:
    return "".join(f"{p}\n" for p in sorted(paths))


def _safe(entry: str) -> bool:
    """A manifest line naming a file inside docs/ (never absolute, never climbing out)."""
    path = PurePosixPath(entry)
    return bool(entry) and not path.is_absolute() and ".." not in path.parts and "\\" not in entry \
        and entry != MANIFEST and ":" not in entry


def _read_manifest(docs_dir: Path) -> list[str] | None:
    path = docs_dir / MANIFEST
    if not path.is_file():
        return None
    return [line for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]


def write_docs(docs_dir: Path) -> list[str]:
    """Write render_docs() into docs_dir (creating dirs), delete generated files no longer produced
    (only files listed in docs/.generated), return the relative paths written or removed."""
    docs_dir = Path(docs_dir)
    rendered = render_docs(*_inputs(docs_dir))
    changed: list[str] = []
    for rel in sorted(set(_read_manifest(docs_dir) or ()) - set(rendered)):
        target = docs_dir / rel
        if _safe(rel) and target.is_file():
            target.unlink()
            changed.append(rel)
            _prune_empty_dirs(target.parent, docs_dir)
    for rel, content in rendered.items():
        target = docs_dir / rel
        if _is_fresh(target, content):
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(_bytes(content))
        changed.append(rel)
    manifest = docs_dir / MANIFEST
    text = _manifest_text(list(rendered)).encode("utf-8")
    if not (manifest.is_file() and manifest.read_bytes() == text):
        manifest.write_bytes(text)
        changed.append(MANIFEST)
    return sorted(changed)


def bench_results(docs_dir: Path) -> Path:
    """The committed benchmark report beside docs/ (benchmarks/results/latest.json of the same checkout)."""
    from ..evaluation.bench import RESULTS_FILE

    return Path(docs_dir).resolve().parent / RESULTS_FILE


def _inputs(docs_dir: Path) -> tuple[Path, ...]:
    """render_docs()'s inputs of the checkout docs_dir is in: the stored reports, baselines and tests beside it."""
    from .ecosystem import OVERHEAD_FILE

    root = Path(docs_dir).resolve().parent
    return (bench_results(docs_dir), fidelity_results(docs_dir), baselines_dir(docs_dir), root / "tests",
            root / OVERHEAD_FILE)


def fidelity_results(docs_dir: Path) -> Path:
    """The committed fidelity suite beside docs/ (benchmarks/results/fidelity.json of the same checkout)."""
    from ..evaluation.fidelity import FIDELITY_FILE

    return Path(docs_dir).resolve().parent / FIDELITY_FILE


def _prune_empty_dirs(directory: Path, root: Path) -> None:
    root = root.resolve()
    directory = directory.resolve()
    while directory != root and root in directory.parents and not any(directory.iterdir()):
        directory.rmdir()
        directory = directory.parent


def stale_docs(docs_dir: Path) -> list[str]:
    """Relative paths that are missing, differ from render_docs(), or are listed in docs/.generated but
    no longer produced (docs/.generated itself if it is missing or omits a produced file).
    Empty list == docs are fresh."""
    docs_dir = Path(docs_dir)
    rendered = render_docs(*_inputs(docs_dir))
    stale = [rel for rel, content in rendered.items() if not _is_fresh(docs_dir / rel, content)]
    listed = _read_manifest(docs_dir)
    if listed is None:
        stale.append(MANIFEST)
    else:
        leftovers = [rel for rel in listed if rel not in rendered]
        stale.extend(leftovers)
        if set(rendered) - set(listed) or len(listed) != len(set(listed)):
            stale.append(MANIFEST)
    return sorted(set(stale))


__all__ = ["render_docs", "write_docs", "stale_docs", "scenario_json_schema", "schema_text"]
