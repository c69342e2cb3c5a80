import itertools

import numpy as np
import pytest


def offsets(ndim, connectivity):
    """Neighbour offsets of a connectivity, in array-axis order."""
    out = []
    for d in itertools.product((-1, 0, 1), repeat=ndim):
        n1 = sum(abs(x) for x in d)
        if n1 == 0:
            continue
        if connectivity in (4, 6) and n1 > 1:
            continue
        if connectivity == 18 and n1 > 2:
            continue
        out.append(d)
    assert len(out) == connectivity
    return np.array(out)


CASES = [(2, 4), (2, 8), (3, 6), (3, 18), (3, 26)]


@pytest.fixture
def rng():
    return np.random.default_rng(20261130)
