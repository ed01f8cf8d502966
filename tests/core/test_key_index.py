"""The compiled key index against a Python dict, under the churn a full FIFO cache makes."""

import numpy as np

from evoplan.key_index import KeyIndex


def test_the_index_answers_as_a_dict_through_inserts_removals_and_growth():
    rng = np.random.default_rng(7)
    index, ref = KeyIndex(), {}
    universe = rng.integers(-(2**62), 2**62, 3000)  # negative keys too: a uint64 seen as int64
    universe[:200] = np.arange(200) << 40  # keys that differ only in their high bits
    for step in range(300):
        keys = rng.choice(universe, 64)
        if step % 3 == 2 and ref:  # drop some present and some absent keys
            gone = rng.choice(np.array(list(ref)), min(len(ref), 40))
            gone = np.concatenate([gone, rng.choice(universe, 5)])
            index.remove(gone)
            for k in gone.tolist():
                ref.pop(k, None)
        else:
            slots = rng.integers(0, 10**6, keys.size)
            index.update(keys, slots)
            ref.update(zip(keys.tolist(), slots.tolist()))
        probe = rng.choice(universe, 500)
        expected = np.array([ref.get(k, -1) for k in probe.tolist()])
        np.testing.assert_array_equal(index.get(probe), expected)
        assert len(index) == len(ref)
    assert index.keys.size > 1024  # it grew past its first table


def test_lookup_gives_each_absent_key_its_first_occurrence_in_the_batch():
    index = KeyIndex()
    index.update(np.array([5, 9]), np.array([0, 1]))
    slot, first = index.lookup(np.array([7, 5, 7, 3, 9, 3, 7]))
    np.testing.assert_array_equal(slot, [-1, 0, -1, -1, 1, -1, -1])
    np.testing.assert_array_equal(first, [0, 1, 0, 3, 4, 3, 0])


def test_row_codes_are_the_integers_the_bits_spell():
    rng = np.random.default_rng(1)
    G = rng.random((50, 48)) < 0.5
    codes, slot, first = KeyIndex().lookup_rows(G, np.arange(48))
    np.testing.assert_array_equal(codes, (G.astype(np.int64) << np.arange(48)).sum(axis=1))
    assert (slot == -1).all()
