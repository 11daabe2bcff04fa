"""Parameter sets of many trajectories as columns (a sweep's chunk of points).

A ``ParamTable`` reads as the list of dicts it stands for (``table[k]`` is trajectory k's
dict, made when asked), so every call that takes a list of parameter sets takes it.  The calls that
pack parameters for many trajectories at once (``NAME_integrate_batch``'s array of structs, the
GPU's parameter array, the Floquet periods of a chunk) read its columns instead of making a
dict per point: at a million points the dicts alone took seconds.
"""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np


class ParamTable(Sequence):
    """``base``: the values every trajectory shares; ``names``: the ones that vary, trajectory k's
    values of them ``values[k]`` (an array of shape (len(self), len(names)))."""

    def __init__(self, base: dict, names: list[str], values):
        self.base = dict(base)
        self.names = list(names)
        self.values = np.asarray(values, dtype=float).reshape(-1, len(self.names))

    def __len__(self) -> int:
        return len(self.values)

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        return {**self.base, **dict(zip(self.names, self.values[k].tolist()))}

    def keys(self) -> list[str]:
        """The names of every set (the shared ones, then the varied ones not among them)."""
        return list(self.base) + [k for k in self.names if k not in self.base]

    def column(self, name: str) -> np.ndarray:
        """The values of ``name`` over the trajectories."""
        if name in self.names:
            return self.values[:, self.names.index(name)]
        return np.full(len(self), float(self.base[name]))

    def fill(self, P: np.ndarray, fields: list[str]) -> None:
        """Write the table into ``P``, an (len(self), len(fields)) array of parameter structs'
        fields (NAME_params, whose members are all REALs): each name's column at its field."""
        for k in self.keys():
            P[:, fields.index(k)] = self.column(k)


__all__ = ["ParamTable"]
