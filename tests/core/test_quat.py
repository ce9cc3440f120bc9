"""Quaternion helpers (wxyz): checked against scipy's independent implementation and by identities."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.spatial.transform import Rotation

from animstudio.core import quat

finite = st.floats(-10.0, 10.0, allow_nan=False)
quats = arrays(np.float64, (4,), elements=finite).filter(lambda q: np.linalg.norm(q) > 1e-2)
vecs = arrays(np.float64, (3,), elements=finite)


def _scipy(q: np.ndarray) -> Rotation:
    return Rotation.from_quat(np.roll(quat.normalize(q), -1, axis=-1))  # scipy is xyzw


def _same(a: np.ndarray, b: np.ndarray, atol: float = 1e-9) -> bool:
    return bool(np.allclose(a, b, atol=atol) or np.allclose(a, -b, atol=atol))


def test_identity_and_about_axes_follow_the_sagittal_convention() -> None:
    np.testing.assert_array_equal(quat.identity((2,)), [[1, 0, 0, 0], [1, 0, 0, 0]])
    # docs/conventions.md: +theta about +Z swings a bone hanging down towards +X (forward).
    down = np.array([0.0, -1.0, 0.0])
    np.testing.assert_allclose(
        quat.rotate(quat.about_z(np.radians(90)), down), [1, 0, 0], atol=1e-12
    )
    np.testing.assert_allclose(
        quat.rotate(quat.about_x(np.pi / 2), [0, 1, 0]), [0, 0, 1], atol=1e-12
    )
    np.testing.assert_allclose(
        quat.rotate(quat.about_y(np.pi / 2), [0, 0, 1]), [1, 0, 0], atol=1e-12
    )


@settings(max_examples=200)
@given(quats)
def test_to_matrix_matches_scipy(q: np.ndarray) -> None:
    np.testing.assert_allclose(quat.to_matrix(q), _scipy(q).as_matrix(), atol=1e-9)


@settings(max_examples=300)
@given(quats)
def test_from_matrix_inverts_to_matrix_with_w_nonnegative(q: np.ndarray) -> None:
    back = quat.from_matrix(quat.to_matrix(q))
    assert back[0] >= 0.0
    assert _same(back, quat.normalize(q), atol=1e-8)


def test_from_matrix_handles_every_branch_and_batches() -> None:
    # Rotations of 180 degrees about each axis force each of Shepperd's four branches.
    angles = np.array([0.1, np.pi, np.pi, np.pi])
    axes = np.array([[0.0, 0, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    q = quat.from_axis_angle(axes, angles)
    back = quat.from_matrix(quat.to_matrix(q).reshape(2, 2, 3, 3))
    assert back.shape == (2, 2, 4)
    for a, b in zip(back.reshape(-1, 4), q, strict=True):
        assert _same(a, b)


@settings(max_examples=200)
@given(quats, quats, vecs)
def test_multiply_composes_b_first_then_a(a: np.ndarray, b: np.ndarray, v: np.ndarray) -> None:
    ab = quat.multiply(quat.normalize(a), quat.normalize(b))
    np.testing.assert_allclose(quat.rotate(ab, v), quat.rotate(a, quat.rotate(b, v)), atol=1e-8)
    np.testing.assert_allclose(quat.to_matrix(ab), (_scipy(a) * _scipy(b)).as_matrix(), atol=1e-8)


@given(quats, vecs)
def test_conjugate_undoes_a_rotation(q: np.ndarray, v: np.ndarray) -> None:
    qn = quat.normalize(q)
    np.testing.assert_allclose(quat.rotate(quat.conjugate(qn), quat.rotate(qn, v)), v, atol=1e-8)


@settings(max_examples=100)
@given(quats, quats, st.floats(0.0, 1.0))
def test_slerp_matches_scipy_and_hits_endpoints(a: np.ndarray, b: np.ndarray, t: float) -> None:
    from scipy.spatial.transform import Slerp

    ra, rb = _scipy(a), _scipy(b)
    want = Slerp([0.0, 1.0], Rotation.concatenate([ra, rb]))([t]).as_matrix()[0]
    np.testing.assert_allclose(quat.to_matrix(quat.slerp(a, b, t)), want, atol=1e-6)
    assert _same(quat.slerp(a, b, 0.0), quat.normalize(a), atol=1e-9)


def test_slerp_of_nearly_equal_quaternions_is_finite_and_broadcasts() -> None:
    a = quat.about_z(np.array([0.3, 0.3]))
    b = quat.about_z(np.array([0.3 + 1e-9, 1.0]))
    out = quat.slerp(a, b, np.array([0.5, 0.5]))
    assert np.all(np.isfinite(out))
    np.testing.assert_allclose(out[1], quat.about_z(0.65), atol=1e-12)


def test_broadcasting_over_leading_axes() -> None:
    q = quat.about_z(np.zeros((5, 3)))
    assert q.shape == (5, 3, 4)
    assert quat.to_matrix(q).shape == (5, 3, 3, 3)
    assert quat.rotate(q, np.ones(3)).shape == (5, 3, 3)


@pytest.mark.parametrize("angle", [0.0, 0.5, -2.0, np.pi])
def test_axis_angle_round_trip(angle: float) -> None:
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    q = quat.from_axis_angle(axis, angle)
    np.testing.assert_allclose(
        _scipy(q).as_rotvec(), Rotation.from_rotvec(axis * angle).as_rotvec(), atol=1e-12
    )
