"""The trigonometry-free screen of the longer maneuver windows (issue 17, session 16).

The screen may leave in any row, but must never leave out one whose δ — as the exact
kernel computes it — exceeds the threshold; the rows it leaves in get that exact δ, bit
for bit. Checked here position by position on blocks built to be hard: noisy tracks,
exact lattice steps (ties, windows along the axes), straight lines, zig-zags, windows at
rest (isotropic or degenerate moments), coordinates far from their spread, tiny and NaN
coordinates, windows of 2 to 40 points and thresholds from 0.5° to past 90°.
"""

import numpy as np
import pytest

from wakeline.core.maneuver import (
    BLOCK,
    _angle_diff,
    _block_moments,
    _gathered_moments,
    _headings_of,
    _screen_block,
    _screen_limit,
)


def _blocks(rng, n):
    k = np.arange(n, dtype=float)
    heading = np.cumsum(np.where(rng.random(n) < 0.03, rng.normal(0, 50, n), 0.0))
    step = rng.choice([0.0, 0.5, 5.0, 60.0], n // 40 + 1).repeat(40)[:n]
    noisy = (
        np.cumsum(step * np.sin(np.radians(heading))),
        np.cumsum(step * np.cos(np.radians(heading))),
    )
    yield noisy[0] + rng.normal(0, 20, n), noisy[1] + rng.normal(0, 20, n)
    yield noisy[0] + rng.normal(0, 0.5, n), noisy[1] + rng.normal(0, 0.5, n)
    lattice = rng.choice([[100.0, 0.0], [0.0, 100.0], [-100.0, 0.0], [0.0, -100.0]], n)
    lattice = np.cumsum(np.repeat(lattice[::7], 7, axis=0)[:n], axis=0)
    yield lattice[:, 0], lattice[:, 1]
    yield k * 30.0, k * 40.0  # a straight line
    yield k * 30.0, np.where(k % 2 == 0, 0.0, 10.0)  # zig-zag
    yield np.zeros(n), np.zeros(n)  # at rest: no axis at all
    yield np.where(k % 2 == 0, 1.0, -1.0), np.where(k % 4 < 2, 1.0, -1.0)  # isotropic
    yield 6.0e6 + k * 3.0 + rng.normal(0, 1, n), -4.0e6 + rng.normal(0, 1, n)  # far away
    yield 1e-200 * (k + rng.random(n)), 1e-200 * rng.random(n)  # tiny
    u, v = noisy[0] + rng.normal(0, 20, n), noisy[1] + rng.normal(0, 20, n)
    u[n // 3] = np.nan
    yield u, v


@pytest.mark.parametrize("p", [2, 3, 5, 8, 11, 12, 16, 17, 32, 40])
def test_the_screen_never_leaves_out_a_row_above_the_threshold(p):
    rng = np.random.default_rng(p)
    n = 3000
    for u, v in _blocks(rng, n):
        exact = _headings_of(u, v, p)  # the kernel's headings, windows ending at each row
        k = n - 2 * (p - 1)
        want = _angle_diff(exact[p - 1 : p - 1 + k], exact[2 * (p - 1) :])  # δ of positions
        is_pos = rng.random(k) < 0.9
        for t in (0.5, 5.0, 15.0, 45.0, 60.0, 85.0, 89.99, 120.0):
            with np.errstate(invalid="ignore"):
                j, d = _screen_block(u, v, p, _screen_limit(t), is_pos)
                above = np.flatnonzero(is_pos & (want > t))
            assert np.isin(above, j).all(), (p, t)
            assert is_pos[j].all()
            assert np.array_equal(d.view("int64"), want[j].view("int64"))


@pytest.mark.parametrize("p", [2, 3, 4, 5, 7, 8, 10, 11, 12, 16, 33])
def test_gathered_window_moments_equal_the_block_bit_for_bit(p):
    rng = np.random.default_rng(100 + p)
    u = np.cumsum(rng.normal(30.0, 5.0, 3000)) + rng.normal(0, 20.0, 3000)
    v = np.cumsum(rng.normal(-10.0, 5.0, 3000)) + rng.normal(0, 20.0, 3000)
    u[::5] = -0.0  # signed zeros and ties
    v[::7] = 0.0
    want = _block_moments(u, v, p)
    for n_ends in (1, 7, 400):
        ends = np.sort(rng.choice(np.arange(p - 1, len(u)), n_ends, replace=False))
        got = _gathered_moments(u, v, p, ends)
        for w, g in zip(want, got, strict=True):
            assert np.array_equal(w[ends - (p - 1)].view("int64"), g.view("int64"))


def test_a_block_of_the_kernel_size():
    # the kernel's own block length, windows across it
    rng = np.random.default_rng(3)
    n = BLOCK + 2 * 7
    u = np.cumsum(rng.normal(20, 4, n))
    v = np.cumsum(rng.normal(-5, 4, n))
    exact = _headings_of(u, v, 8)
    want = _angle_diff(exact[7 : 7 + BLOCK], exact[14:])
    j, d = _screen_block(u, v, 8, _screen_limit(15.0), np.ones(BLOCK, dtype=bool))
    assert np.isin(np.flatnonzero(want > 15.0), j).all()
    assert np.array_equal(d.view("int64"), want[j].view("int64"))
    assert len(j) < 2 * (want > 15.0).sum() + 100  # and it does screen
