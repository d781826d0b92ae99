"""Networks for :class:`~.observations.LabelImage` (need torch, extra ``rl``).

SB3's ``NatureCNN`` needs images of at least 36x36 (8x8 and 4x4 strided kernels); a 10x10 label
map wants small kernels with padding, so that every cell, and the agent's place among its
neighbours, survives.

* :class:`GridCNN`: a features extractor for SB3's ``CnnPolicy`` (convolutions, then a dense
  layer, then the policy's dense action head over all ``2 x size x size`` actions).
* :class:`SpatialPolicy`: fully convolutional, with a *spatial* action head, as the FullyConv
  agent of DeepMind's StarCraft II environment (Vinyals et al., 2017): the logit of a primitive
  at cell ``(i, j)`` is read off the feature map at ``(i, j)`` by a 1x1 convolution, so the same
  weights judge every cell ("navigate to a cell beside unexplored ones, then sense") and the
  policy is translation-equivariant. The value head is dense. It needs actions flattened in C
  order over ``[primitive, i, j]``, as :class:`~.wrappers.FlatActions` numbers them.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch
from gymnasium import spaces
from sb3_contrib.common.maskable.policies import MaskableActorCriticPolicy
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor


def _convolutions(depth: int, channels: int, layers: int) -> list[torch.nn.Module]:
    modules: list[torch.nn.Module] = []
    for k in range(layers):
        modules += [torch.nn.Conv2d(depth if k == 0 else channels, channels, 3, padding=1),
                    torch.nn.ReLU()]
    return modules


class GridCNN(BaseFeaturesExtractor):
    """Two 3x3 convolutions with padding (``channels`` each, ReLU), then one linear layer to
    ``features_dim`` (ReLU)."""

    def __init__(self, observation_space: spaces.Box, features_dim: int = 256,
                 channels: int = 32):
        super().__init__(observation_space, features_dim)
        depth, height, width = observation_space.shape
        self.net = torch.nn.Sequential(
            *_convolutions(depth, channels, 2), torch.nn.Flatten(),
            torch.nn.Linear(channels * height * width, features_dim), torch.nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return self.net(observations)


class GridFeatureMap(BaseFeaturesExtractor):
    """``layers`` 3x3 convolutions with padding (``channels`` each, ReLU), flattened: the
    feature map of every cell, for :class:`SpatialPolicy`."""

    def __init__(self, observation_space: spaces.Box, channels: int = 32, layers: int = 3):
        depth, height, width = observation_space.shape
        super().__init__(observation_space, channels * height * width)
        self.shape = (channels, height, width)
        self.net = torch.nn.Sequential(*_convolutions(depth, channels, layers),
                                       torch.nn.Flatten())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return self.net(observations)


class SpatialHeads(torch.nn.Module):
    """The actor's and critic's latents from a flattened feature map of ``shape``: the actor's
    are the action logits, a 1x1 convolution to ``primitives`` channels flattened in C order;
    the critic's a dense ReLU layer of ``value_units``."""

    def __init__(self, shape: tuple[int, int, int], primitives: int, value_units: int = 64):
        super().__init__()
        self.shape = shape
        channels, height, width = shape
        self.latent_dim_pi = primitives * height * width
        self.latent_dim_vf = value_units
        self.actor = torch.nn.Conv2d(channels, primitives, 1)
        self.critic = torch.nn.Sequential(torch.nn.Linear(channels * height * width, value_units),
                                          torch.nn.ReLU())

    def forward(self, features: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        return self.forward_actor(features), self.forward_critic(features)

    def forward_actor(self, features: torch.Tensor) -> torch.Tensor:
        return self.actor(features.view(-1, *self.shape)).flatten(1)

    def forward_critic(self, features: torch.Tensor) -> torch.Tensor:
        return self.critic(features)


class SpatialPolicy(MaskableActorCriticPolicy):
    """MaskablePPO's actor-critic with :class:`GridFeatureMap` and :class:`SpatialHeads`: the
    action logits come straight from the feature map (no dense layer over all actions)."""

    def __init__(self, observation_space: spaces.Box, action_space: spaces.Discrete,
                 lr_schedule: Any, channels: int = 32, layers: int = 3, **kwargs: Any):
        size = observation_space.shape[1:]
        if action_space.n % int(np.prod(size)):
            raise ValueError(f"SpatialPolicy: {action_space.n} actions are not a whole number "
                             f"of primitives over the {size} grid")
        self.primitives = action_space.n // int(np.prod(size))
        kwargs.update(features_extractor_class=GridFeatureMap, net_arch=[],
                      features_extractor_kwargs={"channels": channels, "layers": layers})
        self.channels, self.layers = channels, layers
        super().__init__(observation_space, action_space, lr_schedule, **kwargs)

    def _build_mlp_extractor(self) -> None:
        self.mlp_extractor = SpatialHeads(self.features_extractor.shape, self.primitives)

    def _build(self, lr_schedule: Any) -> None:
        super()._build(lr_schedule)
        self.action_net = torch.nn.Identity()  # the logits are the actor's latent
        if self.ortho_init:  # SB3's small initial gain of the action layer, on the 1x1 conv
            self.mlp_extractor.actor.apply(lambda m: self.init_weights(m, gain=0.01))
        self.optimizer = self.optimizer_class(self.parameters(), lr=lr_schedule(1),
                                              **self.optimizer_kwargs)

    def _get_constructor_parameters(self) -> dict[str, Any]:
        data = super()._get_constructor_parameters()
        for key in ("features_extractor_class", "features_extractor_kwargs", "net_arch"):
            data.pop(key, None)
        return {**data, "channels": self.channels, "layers": self.layers}
