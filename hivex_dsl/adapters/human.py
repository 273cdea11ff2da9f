"""``render_mode="human"``: a pygame window showing world 0 (pygame is the optional extra ``window``)."""

from __future__ import annotations

from typing import Optional

import numpy as np

RENDER_MODES = (None, "rgb_array", "human")


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

        pygame.init()
        pygame.display.init()
        self.pygame = pygame
        self.title = title
        self.fps = fps
        self.screen = None
        self.clock = pygame.time.Clock()

    def show(self, frame: np.ndarray) -> None:
        pygame = self.pygame
        height, width = frame.shape[:2]
        if self.screen is None:
            self.screen = pygame.display.set_mode((width, height))
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
        self.pygame.quit()
