"""The vector env's batched action space of a hybrid environment (DBR's and AWS's Dict of a continuous and a
discrete part), and how TorchRL reads it.

``gymnasium.vector.utils.batch_space`` batches a Dict key by key: each part has the slots first, the Dict itself
no batch size. TorchRL 0.11 reads a Dict as a Composite of no batch size, which its GymWrapper refuses for a batched
env (``spec.shape ([]) must match the env batch size``). :class:`SlotDict` is that Dict knowing its slots, and
:func:`teach_torchrl` registers its reading with TorchRL through TorchRL's documented hook,
``torchrl.envs.libs.gym.register_gym_spec_conversion``: a Composite of the slots' batch size.
"""

from __future__ import annotations

import sys
from typing import Any

from gymnasium import spaces
from gymnasium.vector.utils import batch_space

_TAUGHT: list[bool] = []  # one entry once TorchRL has been taught


class SlotDict(spaces.Dict):
    """A Dict action space batched over ``slots`` (each part's space has the slots first)."""

    def __init__(self, batched: spaces.Dict, slots: int):
        super().__init__(batched.spaces)
        self.slots = slots


def slot_space(single: spaces.Space, slots: int) -> spaces.Space:
    """``single`` batched over ``slots``, a Dict as a :class:`SlotDict`."""
    batched = batch_space(single, slots)
    return SlotDict(batched, slots) if isinstance(batched, spaces.Dict) else batched


def teach_torchrl() -> None:
    """Register with TorchRL's GymWrapper how to read a :class:`SlotDict`, if TorchRL is loaded (this never imports
    it: the vector env calls it whenever its action space is read, as GymWrapper does to build its specs); once."""
    gym_lib = sys.modules.get("torchrl.envs.libs.gym")
    if gym_lib is None or _TAUGHT:
        return
    from torchrl.data import Composite

    @gym_lib.register_gym_spec_conversion(SlotDict)
    def _slot_dict(spec: SlotDict, device: Any = None, categorical_action_encoding: bool = False,
                   **_: Any) -> Composite:
        return Composite({key: gym_lib._gym_to_torchrl_spec_transform(
            space, device=device, categorical_action_encoding=categorical_action_encoding)
            for key, space in spec.spaces.items()}, shape=(spec.slots,), device=device)

    _TAUGHT.append(True)
