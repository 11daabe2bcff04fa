"""A sweep's parameter sets as columns (gyrochain.models.paramtable.ParamTable): it reads as the
list of dicts it stands for, and gives the columns the batched calls pack."""
from __future__ import annotations

import numpy as np

from gyrochain.models.paramtable import ParamTable


def test_a_table_reads_as_its_list_of_dicts():
    values = np.array([[0.1, 200.0], [0.2, 250.0], [0.3, 300.0]])
    table = ParamTable({"a": 9.0, "g": 9.81}, ["a", "w"], values)
    dicts = [{"a": 0.1, "g": 9.81, "w": 200.0}, {"a": 0.2, "g": 9.81, "w": 250.0}, {"a": 0.3, "g": 9.81, "w": 300.0}]
    assert len(table) == 3 and list(table) == dicts and table[1] == dicts[1] and table[-1] == dicts[-1]
    assert table[1:] == dicts[1:] and table  # (a non-empty table is true, as a non-empty list)
    assert table.keys() == ["a", "g", "w"]
    assert np.array_equal(table.column("w"), values[:, 1]) and np.array_equal(table.column("a"), values[:, 0])
    assert np.array_equal(table.column("g"), np.full(3, 9.81))  # a shared value, over every trajectory
    assert all(type(v) is float for d in table for v in d.values())
    assert not ParamTable({}, ["a"], np.empty((0, 1)))


def test_a_table_fills_an_array_of_parameter_structs_by_field():
    table = ParamTable({"g": 9.81, "m": 2.0}, ["w"], np.array([[200.0], [250.0]]))
    P = np.zeros((2, 4))
    table.fill(P, ["w", "x", "m", "g"])  # the struct's order, a field the table does not set left alone
    assert np.array_equal(P, [[200.0, 0.0, 2.0, 9.81], [250.0, 0.0, 2.0, 9.81]])
    assert list(map(list, P[:, [3, 2, 0]])) == [[d["g"], d["m"], d["w"]] for d in table]
