"""lieflow.SO3 / lieflow.SE3: the vectorized Python groups give the C++
library's numbers bit for bit, agree with independent NumPy formulas and
with their own single-element calls, and refuse bad input."""
import math
import os
import struct
import subprocess

import numpy as np
import pytest

import lieflow

RNG = np.random.default_rng(7)


def tangents(n, dof=3):
    """Rotation parts over every regime of the closed forms: tiny (Taylor
    branches), ordinary, near pi, beyond pi; translation parts random."""
    axes = RNG.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = np.concatenate([10.0 ** RNG.uniform(-12, -3, n // 4), RNG.uniform(0.01, 3.0, n // 4),
                             math.pi - 10.0 ** RNG.uniform(-9, -2, n // 4),
                             RNG.uniform(3.2, 6.0, n - 3 * (n // 4))])
    w = axes * angles[:, None]
    if dof == 3:
        return w
    return np.hstack([RNG.normal(size=(n, 3)), w])


def bits(x):
    return [struct.pack("<d", v) for v in np.ravel(x)]


def reference(lines):
    """The C++ library's answers (tests/python/group_reference.cpp)."""
    program = os.environ["LIEFLOW_GROUP_REFERENCE"]
    text = "".join(op + " " + " ".join(float(v).hex() for v in np.ravel(args)) + "\n" for op, args in lines)
    out = subprocess.run([program], input=text, capture_output=True, text=True, check=True).stdout
    return [np.array([float.fromhex(t) for t in row.split()]) for row in out.splitlines()]


def test_so3_matches_the_cpp_library_bit_for_bit():
    w = tangents(200)
    R = lieflow.SO3.exp(w)
    S = lieflow.SO3.exp(tangents(200))
    p = RNG.normal(size=(200, 3))
    q, s = R.quaternion(), S.quaternion()
    cases = [("so3_exp", w, R.quaternion()), ("so3_log", q, R.log()), ("so3_inverse", q, R.inverse().quaternion()),
             ("so3_compose", np.hstack([q, s]), (R * S).quaternion()), ("so3_act", np.hstack([q, p]), R.act(p)),
             ("so3_matrix", q, R.matrix()), ("so3_Jr", w, lieflow.SO3.Jr(w)), ("so3_Jl", w, lieflow.SO3.Jl(w)),
             ("so3_JrInv", w, lieflow.SO3.JrInv(w)), ("so3_JlInv", w, lieflow.SO3.JlInv(w))]
    for op, inputs, python in cases:
        cpp = reference([(op, row) for row in inputs])
        assert len(cpp) == len(inputs)
        for i, row in enumerate(cpp):
            assert bits(row) == bits(python[i]), f"{op} row {i}: {row} vs {python[i]}"


def test_se3_matches_the_cpp_library_bit_for_bit():
    xi = tangents(120, dof=6)
    X = lieflow.SE3.exp(xi)
    Y = lieflow.SE3.exp(tangents(120, dof=6))
    p = RNG.normal(size=(120, 3))
    x = np.hstack([X.quaternion(), X.translation()])
    y = np.hstack([Y.quaternion(), Y.translation()])
    cases = [("se3_exp", xi, x), ("se3_log", x, X.log()),
             ("se3_inverse", x, np.hstack([X.inverse().quaternion(), X.inverse().translation()])),
             ("se3_compose", np.hstack([x, y]), np.hstack([(X * Y).quaternion(), (X * Y).translation()])),
             ("se3_act", np.hstack([x, p]), X.act(p)), ("se3_matrix", x, X.matrix()), ("se3_Adj", x, X.Adj()),
             ("se3_Jr", xi, lieflow.SE3.Jr(xi)), ("se3_JlInv", xi, lieflow.SE3.JlInv(xi))]
    for op, inputs, python in cases:
        cpp = reference([(op, row) for row in inputs])
        for i, row in enumerate(cpp):
            assert bits(row) == bits(python[i]), f"{op} row {i}"


def test_vectorized_calls_equal_single_element_calls():
    w = tangents(40)
    R = lieflow.SO3.exp(w)
    for i in range(len(w)):
        Ri = lieflow.SO3.exp(w[i])
        assert bits(Ri.quaternion()) == bits(R.quaternion()[i])
        assert bits(Ri.log()) == bits(R.log()[i])
        assert bits(lieflow.SO3.Jr(w[i])) == bits(lieflow.SO3.Jr(w)[i])
        assert Ri.matrix().shape == (3, 3) and Ri.log().shape == (3,)
    xi = tangents(40, dof=6)
    X = lieflow.SE3.exp(xi)
    for i in range(len(xi)):
        assert bits(lieflow.SE3.exp(xi[i]).log()) == bits(X.log()[i])
    # A single element pairs with all N (broadcast), as in NumPy.
    p = RNG.normal(size=(40, 3))
    assert np.array_equal(R[3].act(p), np.stack([R[3].act(pi) for pi in p]))


def rodrigues(w):
    """R = I + sin(t)/t W + (1 - cos(t))/t^2 W^2, an independent formula."""
    t = np.linalg.norm(w)
    W = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return np.eye(3) + math.sin(t) / t * W + (1 - math.cos(t)) / t**2 * W @ W


def test_groups_agree_with_independent_formulas():
    w = RNG.normal(size=(50, 3))
    R = lieflow.SO3.exp(w)
    M = R.matrix()
    for i in range(len(w)):
        np.testing.assert_allclose(M[i], rodrigues(w[i]), atol=1e-14)
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", M, M), np.broadcast_to(np.eye(3), M.shape), atol=1e-14)
    # log inverts exp on angles below pi (the rotation vector is unique there).
    small = w / np.maximum(1.0, np.linalg.norm(w, axis=1, keepdims=True) / 3.0)
    np.testing.assert_allclose(lieflow.SO3.exp(small).log(), small, atol=1e-14)
    # from_matrix inverts matrix, up to the quaternion's sign.
    back = lieflow.SO3.from_matrix(M).quaternion()
    sign = np.sign(np.sum(back * R.quaternion(), axis=1))[:, None]
    np.testing.assert_allclose(back * sign, R.quaternion(), atol=1e-15)
    # SE3 acts as R p + t; its matrix is [[R, t], [0, 1]].
    X = lieflow.SE3.exp(RNG.normal(size=(50, 6)))
    p = RNG.normal(size=(50, 3))
    T = X.matrix()
    np.testing.assert_allclose(X.act(p), np.einsum("nij,nj->ni", T[:, :3, :3], p) + T[:, :3, 3], atol=1e-14)
    np.testing.assert_allclose(T[:, 3], np.broadcast_to([0, 0, 0, 1.0], (50, 4)))


def test_right_jacobian_against_finite_differences():
    # exp(w + d) ~ exp(w) exp(Jr(w) d): the columns of Jr by central differences.
    for group, dof in ((lieflow.SO3, 3), (lieflow.SE3, 6)):
        w = RNG.normal(size=dof)
        J = group.Jr(w)
        h = 1e-6
        base_inv = group.exp(w).inverse()
        for k in range(dof):
            e = np.zeros(dof)
            e[k] = h
            column = ((base_inv * group.exp(w + e)).log() - (base_inv * group.exp(w - e)).log()) / (2 * h)
            np.testing.assert_allclose(column, J[:, k], atol=1e-8)
        np.testing.assert_allclose(group.JrInv(w) @ J, np.eye(dof), atol=1e-13)
        np.testing.assert_allclose(group.Jl(w), group.Jr(-w), atol=0)


def test_bad_input_is_refused_naming_the_row():
    with pytest.raises(lieflow.InputError, match=r"quaternion\[1\]"):
        lieflow.SO3.from_quaternion([[1, 0, 0, 0], [2, 0, 0, 0]])
    with pytest.raises(lieflow.InputError, match=r"tangent\[0, 1\]: is not a finite number"):
        lieflow.SO3.exp([[0.0, np.nan, 0.0]])
    with pytest.raises(lieflow.InputError, match=r"shape"):
        lieflow.SO3.exp(np.zeros((4, 2)))
    with pytest.raises(lieflow.InputError, match=r"matrix\[0\]"):
        lieflow.SO3.from_matrix(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(lieflow.InputError, match=r"cannot pair 3 elements with 2"):
        lieflow.SO3.exp(np.zeros((3, 3))) * lieflow.SO3.exp(np.zeros((2, 3)))
    with pytest.raises(lieflow.InputError, match=r"last row"):
        lieflow.SE3.from_matrix(np.ones((4, 4)))
    assert issubclass(lieflow.InputError, ValueError)
