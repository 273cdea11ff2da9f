"""The island under another Perlin noise: Ken Perlin's improved noise, standing for Unity's Mathf.PerlinNoise, put
through the Aerial Wildfire Suppression release's terrain pipeline, against this toolkit's generator.

    python benchmarks/aws_terrain_noise.py [--islands 16] [--levels 1,3,5,10]

Unity's Mathf.PerlinNoise is native code, not in the release's build; its TerrainNoise.GenerateNoiseMap calls it
once an octave at (x - halfWidth + offset) / scale x frequency in single precision, an offset of up to 100,000 units
an octave, sums (noise x 2 - 1) x amplitude, and normalises the map over its own lowest and highest values
(normalizeMode Local); GenerateMapData subtracts the falloff read at i / size, and the mesh stands t^2 x multiplier
x 7 m high (the reward table's note 'The release's terrain assets'). This prints, a level at a time, the share of the
map above 10 m and above 7 m, the peak and the trees the forest rule grows, ours and the pipeline's, over the same
islands' count, and ours read through the release's simplified mesh (every other sample, 14 m apart) as its
raycasts read its terrain (the note records what it printed, issue 52).
"""

from __future__ import annotations

import argparse

import numpy as np

from hivex_dsl.sim.procgen.forest import ForestSpec, place_forest
from hivex_dsl.sim.procgen.noise import fade
from hivex_dsl.sim.procgen.terrain import (Terrain, TerrainSpec, generate_terrain, height_multiplier_for_level,
                                           island_heights, terrain_spec_for_level)

# Ken Perlin's permutation (Improving Noise, 2002)
PERMUTATION = np.array([
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240,
    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88,
    237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83,
    111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186,
    3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17,
    182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129,
    22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238,
    210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184,
    84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195,
    78, 66, 215, 61, 156, 180])
DOUBLED = np.concatenate([PERMUTATION, PERMUTATION])


def _gradient(hashed: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Improved noise's grad(hash, x, y, z) at z = 0."""
    h = hashed & 15
    u = np.where(h < 8, x, y)
    v = np.where(h < 4, y, np.where((h == 12) | (h == 14), x, 0.0))
    return np.where(h & 1, -u, u) + np.where(h & 2, -v, v)


def improved_noise(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Improved Perlin noise on the plane z = 0 at points (x, y) (any shape), mapped onto [0, 1] as Unity's
    Mathf.PerlinNoise is: (n + 1) / 2, so 0.5 at every lattice point."""
    cell_x, cell_y = np.floor(x), np.floor(y)
    ix, iy = cell_x.astype(np.int64) & 255, cell_y.astype(np.int64) & 255
    fx, fy = x - cell_x, y - cell_y
    u, v = fade(fx), fade(fy)
    a, b = DOUBLED[ix] + iy, DOUBLED[ix + 1] + iy
    corner = {key: DOUBLED[DOUBLED[index]] for key, index in (("aa", a), ("ab", a + 1), ("ba", b), ("bb", b + 1))}
    low = (1 - u) * _gradient(corner["aa"], fx, fy) + u * _gradient(corner["ba"], fx - 1, fy)
    high = (1 - u) * _gradient(corner["ab"], fx, fy - 1) + u * _gradient(corner["bb"], fx - 1, fy - 1)
    return ((1 - v) * low + v * high + 1) / 2


def release_heights(rng: np.random.Generator, level: int, spec: TerrainSpec = TerrainSpec()) -> np.ndarray:
    """(size, size) metres: the release's pipeline over improved noise, its octave offsets drawn from ``rng``."""
    size = spec.size
    offsets = rng.integers(-100_000, 100_000, size=(spec.octaves, 2)).astype(np.float64)
    cols, rows = np.meshgrid(np.arange(size, dtype=np.float64), np.arange(size, dtype=np.float64))
    total, amplitude, frequency = np.zeros((size, size)), 1.0, 1.0
    for offset in offsets:
        x = ((cols - size / 2 + offset[0]) / spec.noise_scale * frequency).astype(np.float32)
        y = ((rows - size / 2 + offset[1]) / spec.noise_scale * frequency).astype(np.float32)
        total += (improved_noise(x.astype(np.float64), y.astype(np.float64)) * 2 - 1) * amplitude
        amplitude, frequency = amplitude * spec.persistence, frequency * spec.lacunarity
    value = (total - total.min()) / (total.max() - total.min())
    # the release reads its falloff at i / size, not at i / (size - 1) as this toolkit's map does
    level_spec = spec.model_copy(update={"height_multiplier": height_multiplier_for_level(level)})
    return island_heights(value, np.abs(np.arange(size) / size * 2 - 1), level_spec)


def island_row(heights: np.ndarray, terrain: Terrain, seed: int) -> tuple[float, float, float, int]:
    """(share of the map above 10 m, above 7 m, the peak, the trees the forest rule grows on ``heights`` laid over
    ``terrain``'s extent)."""
    surface = Terrain(heights=heights, cell_m=terrain.cell_m, extent_m=terrain.extent_m, village=terrain.village)
    trees = place_forest(np.random.default_rng(1000 + seed), ForestSpec(), surface.height_at, terrain.village)
    return float((heights > 10).mean()), float((heights > 7).mean()), float(heights.max()), len(trees.positions)


def simplified_mesh(terrain: Terrain) -> Terrain:
    """The release's mesh of the same map: every other inner sample (meshSimplificationIncrement 2), 120 x 120
    vertices 14 m apart over the same 1,666 m, read bilinearly here where the release reads its triangles."""
    coarse = terrain.heights[1:-1:2, 1:-1:2]
    extent = terrain.extent_m * (coarse.shape[0] - 1) * 2 / (terrain.heights.shape[0] - 1)
    return Terrain(heights=coarse, cell_m=extent / (coarse.shape[0] - 1), extent_m=extent, village=terrain.village)


def compare(level: int, islands: int) -> dict[str, np.ndarray]:
    """Means over ``islands`` islands of :func:`island_row`: ours, the release's pipeline over improved noise, and
    our map read through the release's simplified mesh."""
    rows: dict[str, list] = {"ours": [], "improved noise": [], "ours, simplified mesh": []}
    for seed in range(islands):
        terrain = generate_terrain(np.random.default_rng(seed), terrain_spec_for_level(level))
        rows["ours"].append(island_row(terrain.heights, terrain, seed))
        rows["improved noise"].append(island_row(release_heights(np.random.default_rng(seed), level), terrain, seed))
        mesh = simplified_mesh(terrain)
        rows["ours, simplified mesh"].append(island_row(mesh.heights, mesh, seed))
    return {name: np.array(values, dtype=float).mean(axis=0) for name, values in rows.items()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--islands", type=int, default=16)
    parser.add_argument("--levels", default="1,3,5,10")
    args = parser.parse_args(argv)
    for level in (int(part) for part in args.levels.split(",")):
        for name, (above_10, above_7, peak, trees) in compare(level, args.islands).items():
            print(f"level {level} {name}: map above 10 m {above_10:.1%}, above 7 m {above_7:.1%}, peak {peak:.1f} m, "
                  f"trees {trees:,.0f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
