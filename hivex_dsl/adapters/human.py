"""``render_mode="human"``: a pygame window showing world 0 (pygame is the optional extra ``window``).

Without a display (a server, CI without ``SDL_VIDEODRIVER=dummy``) the window is skipped with one
warning and the environment runs on; ``render()`` returns None in human mode, as Gymnasium and
PettingZoo expect.
"""

from __future__ import annotations

import importlib.util
import warnings
from typing import Optional

import numpy as np

RENDER_MODES = (None, "rgb_array", "human")


def available_render_modes() -> list[str]:
    """The render modes this install can give, as ``metadata["render_modes"]`` lists them: "human" only where
    pygame (the ``window`` extra) imports, so a suite that tries every listed mode (PettingZoo's
    ``render_test``) does not meet an ImportError for a mode the environment advertised."""
    return ["rgb_array", "human"] if importlib.util.find_spec("pygame") is not None else ["rgb_array"]


def check_render_mode(render_mode: Optional[str]) -> None:
    if render_mode not in RENDER_MODES:
        raise ValueError(f"render_mode must be None, 'rgb_array' or 'human', got {render_mode!r}")
    if render_mode == "human":
        try:
            import pygame  # noqa: F401
        except ImportError:
            raise ImportError('render_mode="human" needs pygame: pip install "hivex-dsl[window]"') from None


class Window:
    """One pygame window; each :meth:`show` draws an (H, W, 3) uint8 frame and keeps the frame rate."""

    def __init__(self, title: str, fps: int):
        import pygame

        self.pygame = pygame
        self.title = title
        self.fps = fps
        self.screen = None
        self.skipped = False
        self.clock = pygame.time.Clock()

    def show(self, frame: np.ndarray) -> None:
        pygame = self.pygame
        height, width = frame.shape[:2]
        if self.skipped:
            return
        if self.screen is None:
            try:
                pygame.display.init()
                self.screen = pygame.display.set_mode((width, height))
            except pygame.error as exc:
                warnings.warn(f'render_mode="human": no window ({exc}); the environment runs on without one',
                              stacklevel=3)
                self.skipped = True
                return
            pygame.display.set_caption(self.title)
        pygame.event.pump()  # keeps the window responsive
        surface = pygame.surfarray.make_surface(np.ascontiguousarray(frame[..., :3].swapaxes(0, 1)))
        self.screen.blit(surface, (0, 0))
        pygame.display.flip()
        self.clock.tick(self.fps)

    def close(self) -> None:
        if self.screen is not None:
            self.pygame.display.quit()
            self.screen = None


class Rendering:
    """``render()`` and the human window of an adapter that has ``render_mode``, ``core`` and ``compiled``.

    rgb_array: ``render()`` returns world 0's frame; human: every reset and step shows it in a window
    and ``render()`` returns None.
    """

    _window: Optional[Window] = None

    def render(self):
        if self.render_mode == "rgb_array":
            return self.core.render(0)
        return None

    def _show(self) -> None:
        if self.render_mode == "human":
            self._window = self._window or Window(f"hivex {self.compiled.environment}", self.core.sim.render_fps)
            self._window.show(self.core.render(0))

    def _close_window(self) -> None:
        if self._window is not None:
            self._window.close()
            self._window = None
