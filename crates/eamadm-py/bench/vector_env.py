"""Aggregate random-action env steps per second: eamadm's native vector env on Task I against
Gymnasium's SyncVectorEnv of our single env and of FrozenLake8x8, all measured in this run.

Usage: python bench/vector_env.py [--num-envs 1024] [--seconds 2.0]

Actions are drawn inside the timed loop from a seeded numpy Generator (one int64 array per
step), so every rate includes drawing them. The figures depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import eamadm  # noqa: F401  (registers the ids)


def rate(envs: gym.vector.VectorEnv, seconds: float, seed: int = 0) -> float:
    """Env steps per second (calls x num_envs / wall time) over at least ``seconds``."""
    rng = np.random.default_rng(seed)
    n = envs.num_envs
    n_actions = int(envs.single_action_space.n)
    envs.reset(seed=seed)
    for _ in range(10):  # warm-up
        envs.step(rng.integers(0, n_actions, size=n))
    calls = 0
    start = time.perf_counter()
    deadline = start + seconds
    while True:
        for _ in range(20):
            envs.step(rng.integers(0, n_actions, size=n))
        calls += 20
        now = time.perf_counter()
        if now >= deadline:
            return calls * n / (now - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--num-envs", type=int, default=1024)
    parser.add_argument("--seconds", type=float, default=2.0)
    args = parser.parse_args()
    n = args.num_envs
    cases = [
        (
            "eamadm native vector env, Task I",
            gym.make_vec("eamadm/MazeTaskI-v0", num_envs=n, vectorization_mode="vector_entry_point"),
        ),
        (
            "SyncVectorEnv of eamadm MazeTaskI-v0",
            gym.make_vec("eamadm/MazeTaskI-v0", num_envs=n, vectorization_mode="sync"),
        ),
        (
            "SyncVectorEnv of FrozenLake8x8-v1",
            gym.make_vec("FrozenLake8x8-v1", num_envs=n, vectorization_mode="sync"),
        ),
    ]
    rates = []
    print(f"num_envs = {n}, at least {args.seconds} s each")
    for name, envs in cases:
        steps_per_s = rate(envs, args.seconds)
        envs.close()
        rates.append(steps_per_s)
        print(f"{name:<40} {steps_per_s / 1e6:10.2f} M steps/s")
    native = rates[0]
    print(f"ratio native / sync eamadm:     {native / rates[1]:8.1f}x")
    print(f"ratio native / sync FrozenLake: {native / rates[2]:8.1f}x")


if __name__ == "__main__":
    main()
