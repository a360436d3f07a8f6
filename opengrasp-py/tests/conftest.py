import numpy as np
import pytest

import opengrasp as og


@pytest.fixture(scope="session")
def planar():
    return og.Robot.planar_arm([0.5, 0.4])


@pytest.fixture(scope="session")
def rng():
    return np.random.default_rng(7)
