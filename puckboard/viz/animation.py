"""Animations (GIF, MP4) rendered from a recording, never captured from a screen.

Every frame is drawn off-screen by matplotlib's Agg renderer from the recorded states,
so the file is the same whether the run was watched in a window or ran headless on a
server, and the same seed gives the same file. GIFs are written by Pillow, MP4s by
imageio with its ffmpeg plugin (``pip install 'puckboard[video]'``).

A run is recorded every control cycle (20 Hz for the usual 50 ms step); the animation
samples it at ``fps`` frames per second of *video* and plays ``speed`` times faster
than real time, so a two-minute run becomes a 30-second GIF of 300 frames by default.
"""

from __future__ import annotations

import logging
import math
import os
import time as _time
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import PuckboardError
from ..recording.recorder import Recording

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from PIL.Image import Image

    from ..scenario.scene import Scene
    from .stage import Stage

#: One frame of an animation: height × width × 3 RGB bytes (:meth:`Stage.frame_rgb`).
Frame = np.ndarray

__all__ = [
    "ANIMATION_SUFFIXES",
    "MAX_SIZE",
    "VideoSupportError",
    "check_animation_path",
    "check_size",
    "frame_indices",
    "render_animation",
    "stage_for_recording",
]

log = logging.getLogger(__name__)

ANIMATION_SUFFIXES = (".gif", ".mp4")

GIF_SIZE = (800, 450)
MP4_SIZE = (1280, 720)
MIN_SIZE = (160, 90)
MAX_SIZE = (3840, 2160)
"""The largest animation (pixels): 4K UHD, the largest common screen. Each frame is held
as RGBA (33 MB at this size); a size of 100000x100000 would ask for 40 GB per frame and
end in the allocator's own error after a long wait."""
GIF_COLOURS = 64
"""Palette size of GIFs: the pictures are flat colours, and 64 instead of 256 makes a
file about a quarter smaller with no visible difference."""


class VideoSupportError(PuckboardError, ImportError):
    """MP4 output was asked for but imageio's ffmpeg plugin is not installed (an
    ImportError too, so callers that catch missing packages catch it)."""


def check_animation_path(path: str | os.PathLike[str]) -> Path:
    """Check that ``path`` names an animation this installation can write; fail early
    (before a long run) with the command that fixes it."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in ANIMATION_SUFFIXES:
        raise ValueError(f"cannot write an animation to {str(p)!r}: use a .gif or .mp4 file name")
    try:
        import matplotlib  # noqa: F401
        import PIL  # noqa: F401
    except ImportError as exc:
        raise VideoSupportError(
            f"animations need matplotlib and Pillow ({exc.name} is missing): "
            "pip install 'puckboard[viz]'"
        ) from exc
    if suffix == ".mp4":
        try:
            import imageio  # noqa: F401
            import imageio_ffmpeg  # noqa: F401
        except ImportError as exc:
            raise VideoSupportError(
                "MP4 support is not installed (imageio-ffmpeg is missing): "
                "pip install 'puckboard[video]', or record a .gif instead"
            ) from exc
    return p


def frame_indices(
    rec: Recording,
    fps: float,
    speed: float,
    start: float | None = None,
    end: float | None = None,
) -> np.ndarray:
    """Recording rows shown by each frame: one every ``speed / fps`` seconds of run time,
    from ``start`` to ``end`` (s of run time; default: all of it)."""
    if fps <= 0 or speed <= 0:
        raise ValueError(f"fps and speed must be positive, got fps={fps}, speed={speed}")
    if len(rec) == 0:
        return np.zeros(0, dtype=int)
    t = rec.time
    t0 = t[0] if start is None else max(t[0], start)
    t1 = t[-1] if end is None else min(t[-1], end)
    if t1 < t0:
        if start is not None and end is not None:
            window = f"between {start:g} s and {end:g} s"
        else:
            window = f"from {start:g} s on" if start is not None else f"up to {end:g} s"
        raise ValueError(f"nothing to animate {window}: the run covers {t[0]:.2f} to {t[-1]:.2f} s")
    n = int(math.floor((t1 - t0) * fps / speed + 1e-9)) + 1
    wanted = t0 + np.arange(n) * (speed / fps)
    idx = np.clip(np.searchsorted(t, wanted - 1e-9), 0, len(t) - 1)
    last = int(np.searchsorted(t, t1 + 1e-9) - 1)
    if end is None or end >= t[-1]:
        last = len(t) - 1
    if idx[-1] != last:  # always end on the final state: how a run ends matters most
        idx = np.append(idx, last)
    return idx


def stage_for_recording(fig: Figure, rec: Recording, **options: Any) -> Stage:
    """A :class:`~puckboard.viz.stage.Stage` on ``fig`` set up for ``rec``'s robots."""
    from .stage import Stage
    from .style import layer_order, robot_colours

    layers = layer_order(rec.robot(name).layers for name in rec.robot_names)
    scene = rec.scene
    bounds = _bounds(scene, rec.pose[..., :2])
    return Stage(
        fig,
        scene,
        rec.robot_names,
        colours=robot_colours(rec.robot_names, rec.meta.get("colours")),
        layers=layers,
        title=rec.title,
        bounds=bounds,
        cycle=float(rec.meta.get("dt") or 0.05),
        **options,
    )


def _bounds(scene: Scene | None, xy: np.ndarray) -> tuple[float, float, float, float]:
    """The scene's extent, grown to show where the robots went, but never more than half
    the scene's size again (a robot driving off must not shrink the scene to a dot)."""
    from .scene_art import scene_bounds

    if scene is None:
        return scene_bounds(None, xy)  # type: ignore[no-any-return]
    x0, x1, y0, y1 = scene_bounds(scene)
    px0, px1, py0, py1 = scene_bounds(None, xy)
    gx, gy = 0.5 * (x1 - x0), 0.5 * (y1 - y0)
    return (
        max(min(x0, px0), x0 - gx),
        min(max(x1, px1), x1 + gx),
        max(min(y0, py0), y0 - gy),
        min(max(y1, py1), y1 + gy),
    )


def _layer_names(rec: Recording, i: int) -> list[str | None]:
    return [rec.layer_names[k] if k >= 0 else None for k in rec.layer[i]]


def draw_row(stage: Stage, rec: Recording, i: int, trail_start: int = 0) -> None:
    """Show recording row ``i`` on ``stage`` with trails from ``trail_start``."""
    trails = [rec.pose[trail_start : i + 1, r, :2] for r in range(len(rec.robot_names))]
    stage.update(
        float(rec.time[i]), rec.pose[i], rec.proximity[i], rec.ground[i], _layer_names(rec, i),
        trails, rec.meta.get("events") or (),
    )  # fmt: skip


def check_size(width: int, height: int) -> tuple[int, int]:
    """``(width, height)`` if an animation can be that size (:data:`MIN_SIZE` to
    :data:`MAX_SIZE` pixels), else a ``ValueError`` saying what fits; checked before
    anything is allocated."""
    (w_min, h_min), (w_max, h_max) = MIN_SIZE, MAX_SIZE
    if width < w_min or height < h_min:
        raise ValueError(f"size must be at least {w_min}x{h_min} pixels, got {width}x{height}")
    if width > w_max or height > h_max:
        raise ValueError(
            f"size must be at most {w_max}x{h_max} pixels (4K; each frame is held in memory), "
            f"got {width}x{height}"
        )
    return width, height


def render_animation(
    rec: Recording,
    path: str | os.PathLike[str],
    *,
    fps: float = 10.0,
    speed: float = 4.0,
    size: tuple[int, int] | None = None,
    start: float | None = None,
    end: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> dict[str, Any]:
    """Render ``rec`` to ``path`` (.gif or .mp4); returns what was written.

    ``start``/``end`` (s of run time) animate only part of the run; the trails still
    show the path from the beginning.
    ``size`` is (width, height) in pixels (default 800×450 for GIF, 1280×720 for MP4).
    ``progress(done, total)`` is called after each frame. The result holds ``path``,
    ``frames``, ``size``, ``fps``, ``speed``, ``bytes`` and ``seconds_per_frame``.
    """
    path = check_animation_path(path)
    if len(rec) == 0:
        raise ValueError("the recording is empty: nothing to animate")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    gif = path.suffix.lower() == ".gif"
    width, height = check_size(*(size or (GIF_SIZE if gif else MP4_SIZE)))
    dpi = 100.0 * width / 1280.0  # the layout is designed at 1280×720, 100 dpi
    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    stage = stage_for_recording(fig, rec)
    indices = frame_indices(rec, fps, speed, start, end)
    path.parent.mkdir(parents=True, exist_ok=True)
    t0 = _time.perf_counter()

    def frames() -> Iterator[Frame]:
        for k, i in enumerate(indices):
            draw_row(stage, rec, int(i))
            yield stage.frame_rgb()
            if progress is not None:
                progress(k + 1, len(indices))

    if gif:
        _write_gif(path, frames(), fps, rec, stage, indices)
    else:
        _write_mp4(path, frames(), fps)
    elapsed = _time.perf_counter() - t0
    result: dict[str, Any] = {
        "path": path,
        "frames": len(indices),
        "size": (width, height),
        "fps": fps,
        "speed": speed,
        "bytes": path.stat().st_size,
        "seconds_per_frame": elapsed / max(1, len(indices)),
    }
    log.info(
        "wrote %s: %d frames %dx%d, %.1f kB, %.1f ms per frame",
        path, len(indices), width, height, result["bytes"] / 1e3, 1e3 * result["seconds_per_frame"],
    )  # fmt: skip
    return result


def _palette(rec: Recording, stage: Stage, indices: np.ndarray) -> Image:
    """One palette for the whole GIF, from a few frames spread over the run: frames share
    it, so colours never flicker and unchanged pixels compress to nothing."""
    from PIL import Image

    picks = np.unique(indices[np.linspace(0, len(indices) - 1, min(6, len(indices))).astype(int)])
    tiles = []
    for i in picks:
        draw_row(stage, rec, int(i))
        tiles.append(stage.frame_rgb())
    sheet = Image.fromarray(np.concatenate(tiles, axis=0))
    # The colours that carry meaning (layers, robots, rays) get exact palette entries;
    # median cut would merge a small legend swatch into its neighbour.
    exact = [_rgb(c) for c in stage.key_colours()]
    exact = list(dict.fromkeys([(255, 255, 255), (0, 0, 0), *exact]))[: GIF_COLOURS // 2]
    rest = sheet.quantize(colors=GIF_COLOURS - len(exact), method=Image.Quantize.MEDIANCUT)
    rest_pal = (rest.getpalette() or [])[: 3 * (GIF_COLOURS - len(exact))]
    pal = Image.new("P", (1, 1))
    pal.putpalette([v for c in exact for v in c] + rest_pal)
    return pal


def _rgb(colour: Any) -> tuple[int, int, int]:
    from matplotlib.colors import to_rgb

    r, g, b = to_rgb(colour)
    return (round(r * 255), round(g * 255), round(b * 255))


def _write_gif(
    path: Path,
    frames: Iterable[Frame],
    fps: float,
    rec: Recording,
    stage: Stage,
    indices: np.ndarray,
) -> None:
    from PIL import Image

    palette = _palette(rec, stage, indices)
    images = [
        Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.NONE) for f in frames
    ]
    tmp = path.with_name(path.name + ".part")
    try:
        images[0].save(
            tmp,
            format="GIF",
            save_all=True,
            append_images=images[1:],
            duration=max(20, round(1000.0 / fps / 10.0) * 10),
            loop=0,
            optimize=False,
            disposal=1,
        )
    except BaseException:  # Ctrl-C or a full disk: leave no half-written file behind
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, path)


def _write_mp4(path: Path, frames: Iterable[Frame], fps: float) -> None:
    import imageio.v2 as imageio

    tmp = path.with_name(path.stem + ".part.mp4")
    writer = imageio.get_writer(
        tmp, fps=fps, codec="libx264", quality=7, pixelformat="yuv420p", macro_block_size=8
    )
    try:
        for frame in frames:
            writer.append_data(frame)
    except BaseException:  # Ctrl-C or a full disk: leave no half-written file behind
        writer.close()
        tmp.unlink(missing_ok=True)
        raise
    writer.close()
    os.replace(tmp, path)
