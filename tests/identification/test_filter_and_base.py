"""The derivative filter against SciPy's Savitzky-Golay, and the base parameters of hand-made regressors."""

import numpy as np
import pytest
from scipy.signal import savgol_filter

from lagrangian.errors import IdentificationError
from lagrangian.identification import SavitzkyGolay, base_parameters


def test_derivatives_on_a_uniform_grid_are_scipys_savitzky_golay():
    t = np.linspace(0.0, 2.0, 401)
    x = np.sin(3 * t) + 0.1 * t**2
    value, rate, acceleration = SavitzkyGolay(21, 4).derivatives(t, x)
    h = t[1] - t[0]
    inner = slice(10, -10)  # SciPy's default mode="interp" fits the ends differently
    np.testing.assert_allclose(value[inner], savgol_filter(x, 21, 4)[inner], atol=1e-12)
    np.testing.assert_allclose(rate[inner], savgol_filter(x, 21, 4, deriv=1, delta=h)[inner], atol=1e-9)
    np.testing.assert_allclose(acceleration[inner], savgol_filter(x, 21, 4, deriv=2, delta=h)[inner], atol=1e-7)


def test_derivatives_of_a_polynomial_are_exact_on_an_uneven_grid():
    t = np.sort(np.random.default_rng(0).uniform(0.0, 2.0, 301))
    x = np.column_stack([1 - 2 * t + t**3, 0.5 * t**4])
    _, rate, acceleration = SavitzkyGolay(15, 4).derivatives(t, x)
    np.testing.assert_allclose(rate, np.column_stack([-2 + 3 * t**2, 2 * t**3]), atol=1e-9)
    np.testing.assert_allclose(acceleration, np.column_stack([6 * t, 6 * t**2]), atol=1e-7)


@pytest.mark.parametrize("window, order", [(20, 4), (1, 0), (5, 5), (7, 1)])
def test_a_filter_that_cannot_give_accelerations_is_refused(window, order):
    with pytest.raises(IdentificationError):
        SavitzkyGolay(window, order)


def test_base_parameters_of_a_regressor_with_a_sum_and_a_dead_column():
    # columns a, b, c, d with c = 2 a − b and d ≡ 0: θ_a + 2 θ_c and θ_b − θ_c are what Y shows
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(2, 50))
    Y = np.column_stack([a, b, 2 * a - b, np.zeros(50)])
    base = base_parameters(Y, ["a", "b", "c", "d"])
    assert base.rank == 2 and base.zero == (3,)
    assert base.combinations() == ["a + 2 c", "b - c"]
    theta = np.array([0.3, -1.2, 0.7, 5.0])
    np.testing.assert_allclose(Y[:, list(base.independent)] @ (base.matrix() @ theta), Y @ theta, atol=1e-12)
    assert base.alone() == []


def test_base_parameters_scale_columns_of_different_units_alike():
    # a column a thousand times larger than another independent one is not mistaken for rank one
    rng = np.random.default_rng(2)
    Y = np.column_stack([1e3 * rng.normal(size=40), 1e-3 * rng.normal(size=40)])
    assert base_parameters(Y, ["big", "small"]).full
