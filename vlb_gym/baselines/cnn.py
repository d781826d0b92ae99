"""A features extractor for :class:`~.observations.LabelImage` (needs torch, extra ``rl``).

SB3's ``NatureCNN`` needs images of at least 36x36 (8x8 and 4x4 strided kernels); a 10x10 label
map wants small kernels with padding, so that every cell, and the agent's place among its
neighbours, survives to the linear layer.
"""

from __future__ import annotations

import torch
from gymnasium import spaces
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor


class GridCNN(BaseFeaturesExtractor):
    """Two 3x3 convolutions with padding (``channels`` each, ReLU), then one linear layer to
    ``features_dim`` (ReLU)."""

    def __init__(self, observation_space: spaces.Box, features_dim: int = 256,
                 channels: int = 32):
        super().__init__(observation_space, features_dim)
        depth, height, width = observation_space.shape
        self.net = torch.nn.Sequential(
            torch.nn.Conv2d(depth, channels, 3, padding=1), torch.nn.ReLU(),
            torch.nn.Conv2d(channels, channels, 3, padding=1), torch.nn.ReLU(),
            torch.nn.Flatten(),
            torch.nn.Linear(channels * height * width, features_dim), torch.nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return self.net(observations)
