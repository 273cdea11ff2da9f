"""Top-down RGB drawing of a square world region with whole-array NumPy.

World coordinates are metres, +x to the right and +y up. Pixel coordinates are
float (col, row) pairs with (0, 0) the top-left corner of the picture; pixel
(row r, col c) covers [c, c + 1) x [r, r + 1) and its centre is (c + 0.5, r + 0.5).

Shapes are rasterised by testing pixel centres inside each shape's bounding box
only. The boxes of all N shapes of one call are flattened into one ragged batch,
so no Python loop runs over pixels or shapes. Within one call a later shape
paints over an earlier one (resolved explicitly, not by NumPy's unspecified
order of repeated fancy-index assignment).
"""

from __future__ import annotations

import numpy as np

from ...base.errors import is_integer

Color = tuple[int, int, int]

# Seven samples of matplotlib's viridis (dark blue -> teal -> yellow); luminance rises monotonically.
VIRIDIS_STOPS = np.array(
    [[68, 1, 84], [68, 58, 131], [49, 104, 142], [33, 144, 140],
     [53, 183, 121], [143, 215, 68], [253, 231, 37]],
    dtype=np.uint8,
)
VIRIDIS_STOPS.setflags(write=False)


# ----------------------------------------------------------------------------- argument checks
def _points(values, name: str) -> np.ndarray:
    """Validate finite (N, 2) coordinates; returns float64 (N, 2)."""
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (N, 2), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr


def _per_shape(value, n: int, name: str, positive: bool = False) -> np.ndarray:
    """A scalar or (n,) finite non-negative (or strictly positive) value -> float64 (n,)."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},), got {arr.shape}")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0 if positive else arr < 0):
        raise ValueError(f"{name} must be finite and {'> 0' if positive else '>= 0'}")
    return arr


def _uint8(values, name: str) -> np.ndarray:
    """Numbers in [0, 255] (any shape) -> uint8 of the same shape, rounded to nearest."""
    arr = np.asarray(values)
    if arr.dtype == np.uint8:
        return arr
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be numeric 0..255, got dtype {arr.dtype}")
    if not np.all(np.isfinite(arr)) or np.any((arr < 0) | (arr > 255)):
        raise ValueError(f"{name} must lie in [0, 255]")
    return np.rint(arr).astype(np.uint8)


def _colors(colors, n: int) -> np.ndarray:
    """One (3,) colour or (n, 3) colours -> uint8 (n, 3)."""
    arr = _uint8(colors, "colors")
    if arr.shape == (3,):
        return np.broadcast_to(arr, (n, 3))
    if arr.shape != (n, 3):
        raise ValueError(f"colors must have shape (3,) or ({n}, 3), got {arr.shape}")
    return arr


# ----------------------------------------------------------------------------- canvas
class Canvas:
    """An RGB uint8 picture of the square world region [-half_extent, half_extent]^2 seen from above:
    +x to the right, +y UP (row 0 is the top, i.e. y = +half_extent).

    size_px: picture width = height in pixels; half_extent: metres; background: RGB 0..255.
    `pixels` is the writable (size_px, size_px, 3) uint8 picture.
    """

    def __init__(self, size_px: int, half_extent: float, background: Color = (255, 255, 255)):
        if not is_integer(size_px) or size_px < 1:
            raise ValueError(f"size_px must be a positive integer, got {size_px!r}")
        half_extent = float(half_extent)
        if not (np.isfinite(half_extent) and half_extent > 0):
            raise ValueError(f"half_extent must be finite and > 0, got {half_extent!r}")
        self.size_px = int(size_px)
        self.half_extent = half_extent
        self.px_per_m = self.size_px / (2.0 * half_extent)
        self.pixels = np.empty((self.size_px, self.size_px, 3), dtype=np.uint8)
        self.pixels[...] = _colors(background, 1)[0]
        self._centres: tuple[np.ndarray, np.ndarray] | None = None

    # -- coordinates
    def to_pixel(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) world metres -> (N, 2) float (col, row); (-h, +h) -> (0, 0), (+h, -h) -> (S, S)."""
        return self._to_px(_points(xy, "xy"))

    def _to_px(self, xy: np.ndarray) -> np.ndarray:
        """to_pixel for already validated (N, 2) float metres."""
        h = self.half_extent
        return np.stack([(xy[:, 0] + h) * self.px_per_m, (h - xy[:, 1]) * self.px_per_m], axis=1)

    def pixel_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """World x and y (metres) of every pixel centre, two read-only (H, W) arrays (cached)."""
        if self._centres is None:
            offsets = (np.arange(self.size_px) + 0.5) / self.px_per_m
            shape = (self.size_px, self.size_px)
            x = np.ascontiguousarray(np.broadcast_to(offsets - self.half_extent, shape))
            y = np.ascontiguousarray(np.broadcast_to((self.half_extent - offsets)[:, None], shape))
            x.setflags(write=False)
            y.setflags(write=False)
            self._centres = (x, y)
        return self._centres

    # -- rasterisation core
    def _box_pixels(self, lo: np.ndarray, hi: np.ndarray):
        """All pixels whose cells meet each shape's box [lo, hi] ((N, 2) pixel (col, row) floats),
        clipped to the picture. Returns int64 (M,) arrays (shape id, row, col), ids ascending."""
        size = self.size_px
        lo_i = np.clip(np.floor(lo), 0, size).astype(np.int64)
        hi_i = np.clip(np.floor(hi) + 1, 0, size).astype(np.int64)
        width, height = (hi_i - lo_i).T
        area = width * height
        ids = np.repeat(np.arange(len(lo)), area)
        local = np.arange(area.sum()) - (np.cumsum(area) - area)[ids]
        box_w = width[ids]
        return ids, lo_i[ids, 1] + local // box_w, lo_i[ids, 0] + local % box_w

    def _paint(self, ids: np.ndarray, rows: np.ndarray, cols: np.ndarray, colors: np.ndarray) -> None:
        """Paint pixel (rows[k], cols[k]) with colors[ids[k]]; the highest shape id wins a pixel."""
        winner = np.full(self.size_px * self.size_px, -1, dtype=np.int64)
        np.maximum.at(winner, rows * self.size_px + cols, ids)
        hit = np.flatnonzero(winner >= 0)
        self.pixels[hit // self.size_px, hit % self.size_px] = colors[winner[hit]]

    @staticmethod
    def _contains_centre(rows, cols, centre_px: np.ndarray) -> np.ndarray:
        """True where the pixel is the one containing centre_px ((M, 2) col, row)."""
        return (cols == np.floor(centre_px[:, 0])) & (rows == np.floor(centre_px[:, 1]))

    # -- shapes
    def fill(self, rgb: np.ndarray) -> None:
        """Paint a whole (H, W, 3) field of 0..255 values (e.g. a colour-mapped scalar field)."""
        rgb = _uint8(rgb, "rgb")
        if rgb.shape != self.pixels.shape:
            raise ValueError(f"rgb must have shape {self.pixels.shape}, got {rgb.shape}")
        self.pixels[...] = rgb

    def disks(self, centres: np.ndarray, radius_m: float | np.ndarray, colors) -> None:
        """Filled disks. centres (N, 2) metres; radius_m scalar or (N,) metres; colors (3,) or (N, 3).
        Later disks paint over earlier ones; a disk smaller than a pixel still paints the pixel
        containing its centre."""
        c = self._to_px(_points(centres, "centres"))
        r = _per_shape(radius_m, len(c), "radius_m") * self.px_per_m
        rgb = _colors(colors, len(c))
        ids, rows, cols = self._box_pixels(c - r[:, None], c + r[:, None])
        d2 = (cols + 0.5 - c[ids, 0]) ** 2 + (rows + 0.5 - c[ids, 1]) ** 2
        inside = (d2 <= r[ids] ** 2) | self._contains_centre(rows, cols, c[ids])
        self._paint(ids[inside], rows[inside], cols[inside], rgb)

    def rings(self, centres: np.ndarray, radius_m: float | np.ndarray, width_px: float | np.ndarray,
              colors) -> None:
        """Circle outlines: pixels whose centre is within width_px / 2 pixels of the circle.
        centres (N, 2) metres; radius_m scalar or (N,) metres; width_px scalar or (N,) pixels."""
        c = self._to_px(_points(centres, "centres"))
        r = _per_shape(radius_m, len(c), "radius_m") * self.px_per_m
        half = _per_shape(width_px, len(c), "width_px", positive=True) / 2.0
        rgb = _colors(colors, len(c))
        reach = (r + half)[:, None]
        ids, rows, cols = self._box_pixels(c - reach, c + reach)
        d = np.hypot(cols + 0.5 - c[ids, 0], rows + 0.5 - c[ids, 1])
        inside = np.abs(d - r[ids]) <= half[ids]
        self._paint(ids[inside], rows[inside], cols[inside], rgb)

    def segments(self, starts: np.ndarray, ends: np.ndarray, width_px: float | np.ndarray, colors) -> None:
        """Thick line segments starts (N, 2) -> ends (N, 2) metres; a pixel is painted when its centre
        lies within width_px / 2 pixels of the segment. width_px scalar or (N,); colors (3,) or (N, 3)."""
        a, b = self._to_px(_points(starts, "starts")), self._to_px(_points(ends, "ends"))
        if a.shape != b.shape:
            raise ValueError(f"starts and ends must have the same shape, got {a.shape} and {b.shape}")
        half = _per_shape(width_px, len(a), "width_px", positive=True) / 2.0
        rgb = _colors(colors, len(a))
        ids, rows, cols = self._box_pixels(np.minimum(a, b) - half[:, None], np.maximum(a, b) + half[:, None])
        ab = (b - a)[ids]
        ap = np.stack([cols + 0.5, rows + 0.5], axis=1) - a[ids]
        len2 = np.einsum("ij,ij->i", ab, ab)
        t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.where(len2 > 0, len2, 1.0), 0.0, 1.0)
        off = ap - t[:, None] * ab
        inside = np.einsum("ij,ij->i", off, off) <= half[ids] ** 2
        self._paint(ids[inside], rows[inside], cols[inside], rgb)

    def arrows(self, tails: np.ndarray, vectors: np.ndarray, width_px: float | np.ndarray, colors,
               head_frac: float = 0.35) -> None:
        """Arrows from tails (N, 2) along vectors (N, 2), both metres: a shaft plus two head strokes
        of length head_frac * |vector| leaving the tip at +/-150 degrees from the arrow direction."""
        tails, vectors = _points(tails, "tails"), _points(vectors, "vectors")
        if tails.shape != vectors.shape:
            raise ValueError(f"tails and vectors must have the same shape, got {tails.shape} and {vectors.shape}")
        if not (np.isfinite(head_frac) and 0.0 <= head_frac <= 1.0):
            raise ValueError(f"head_frac must lie in [0, 1], got {head_frac!r}")
        n = len(tails)
        width = _per_shape(width_px, n, "width_px", positive=True)
        rgb = _colors(colors, n)
        tips = tails + vectors
        cos, sin = np.cos(np.radians(150.0)), np.sin(np.radians(150.0))
        back = vectors * head_frac
        left = tips + back @ np.array([[cos, sin], [-sin, cos]])   # rotated by +150 degrees
        right = tips + back @ np.array([[cos, -sin], [sin, cos]])  # rotated by -150 degrees
        starts = np.stack([tails, tips, tips], axis=1).reshape(-1, 2)
        ends = np.stack([tips, left, right], axis=1).reshape(-1, 2)
        self.segments(starts, ends, np.repeat(width, 3), np.repeat(rgb, 3, axis=0))

    def rectangles(self, lows: np.ndarray, highs: np.ndarray, colors) -> None:
        """Axis-aligned filled boxes [lows, highs], (N, 2) metres each; pixels whose centre lies in the
        box are painted, and a box smaller than a pixel still paints the pixel containing its centre."""
        lows, highs = _points(lows, "lows"), _points(highs, "highs")
        if lows.shape != highs.shape:
            raise ValueError(f"lows and highs must have the same shape, got {lows.shape} and {highs.shape}")
        if np.any(highs < lows):
            raise ValueError("every rectangle needs highs >= lows")
        rgb = _colors(colors, len(lows))
        top_left = self._to_px(np.stack([lows[:, 0], highs[:, 1]], axis=1))
        bottom_right = self._to_px(np.stack([highs[:, 0], lows[:, 1]], axis=1))
        ids, rows, cols = self._box_pixels(top_left, bottom_right)
        lo, hi = top_left[ids], bottom_right[ids]
        inside = ((cols + 0.5 >= lo[:, 0]) & (cols + 0.5 <= hi[:, 0])
                  & (rows + 0.5 >= lo[:, 1]) & (rows + 0.5 <= hi[:, 1]))
        inside |= self._contains_centre(rows, cols, (lo + hi) / 2.0)
        self._paint(ids[inside], rows[inside], cols[inside], rgb)

    def image(self) -> np.ndarray:
        """A copy of the picture, (H, W, 3) uint8."""
        return self.pixels.copy()


# ----------------------------------------------------------------------------- colour helpers
def colormap(values: np.ndarray, low: float = 0.0, high: float = 1.0, stops: np.ndarray | None = None) -> np.ndarray:
    """Map values (any shape) linearly through the colour stops (K, 3), K >= 2, spaced evenly over
    [low, high] (default VIRIDIS_STOPS). Values are clipped to [low, high]; NaN maps like `low`.
    Returns values.shape + (3,) uint8."""
    low, high = float(low), float(high)
    if not (np.isfinite(low) and np.isfinite(high) and low < high):
        raise ValueError(f"need finite low < high, got low={low!r}, high={high!r}")
    ramp = VIRIDIS_STOPS if stops is None else _uint8(stops, "stops")
    if ramp.ndim != 2 or ramp.shape[1] != 3 or len(ramp) < 2:
        raise ValueError(f"stops must have shape (K, 3) with K >= 2, got {ramp.shape}")
    values = np.asarray(values, dtype=float)
    t = (np.clip(np.nan_to_num(values, nan=low), low, high) - low) * ((len(ramp) - 1) / (high - low))
    seg = np.minimum(t.astype(np.int64), len(ramp) - 2)  # t >= 0, so truncation is floor
    frac = t - seg
    base = ramp.astype(float)
    slope = np.diff(base, axis=0)
    out = np.empty(values.shape + (3,), dtype=np.uint8)
    for ch in range(3):  # per-channel 1-D table look-ups are ~10x faster than gathering (..., 3) rows
        out[..., ch] = np.rint(np.take(base[:, ch], seg) + np.take(slope[:, ch], seg) * frac)
    return out

def hue_wheel(angles_rad: np.ndarray, saturation: float = 0.35, value: float = 0.95) -> np.ndarray:
    """Direction colouring: angle (radians, any shape; 0 = red, 2*pi/3 = green, 4*pi/3 = blue) -> pastel
    RGB via HSV with the given saturation and value in [0, 1]. Returns angles.shape + (3,) uint8."""
    for name, x in (("saturation", saturation), ("value", value)):
        if not (np.isfinite(x) and 0.0 <= x <= 1.0):
            raise ValueError(f"{name} must lie in [0, 1], got {x!r}")
    angles = np.asarray(angles_rad, dtype=float)
    if not np.all(np.isfinite(angles)):
        raise ValueError("angles_rad must be finite")
    hue = angles * (3.0 / np.pi)  # sixths of a turn
    hue -= 6.0 * np.floor(hue / 6.0)  # wrap to [0, 6] (np.mod is much slower)
    out = np.empty(angles.shape + (3,), dtype=np.uint8)
    # Continuous HSV -> RGB: channel uses k = (n + hue) mod 6 with n = 5, 3, 1 for R, G, B.
    for ch, n in enumerate((5.0, 3.0, 1.0)):
        k = hue + n
        k -= 6.0 * (k >= 6.0)
        ramp = np.clip(np.minimum(k, 4.0 - k), 0.0, 1.0)
        out[..., ch] = np.rint(255.0 * value * (1.0 - saturation * ramp))
    return out

def upscale(image: np.ndarray, factor: int) -> np.ndarray:
    """Nearest-neighbour enlarge an (H, W, 3) image to (H * factor, W * factor, 3), same dtype."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"image must have shape (H, W, 3), got {image.shape}")
    if not is_integer(factor) or factor < 1:
        raise ValueError(f"factor must be a positive integer, got {factor!r}")
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)
