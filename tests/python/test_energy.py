"""ringlet.energy, ringlet.gradient and ringlet.hessian (issue 25, item 6): the gradient against
central differences of the energy, the Hessian against central differences of the gradient
(with and without body contact), the elastic energy against eq. 3 written out here and 0 at the
rest shape, the gravity energy of a straight strand in closed form, and the gradient at a solved
equilibrium against the solver's tolerance (its residual computed here from the definition)."""
import numpy as np
import pytest

import ringlet

RNG = np.random.default_rng(6)


def curly_model(segments=6, rest=False):
    model = ringlet.StrandModel(ringlet.graded_segments(0.12, segments, 1.5),
                                ringlet.section_from_eccentricity(40e-6, 0.4),
                                natural_curvature=(60.0, -10.0, 15.0),
                                root_frame=[[1, 0, 0], [0, -1, 0], [0, 0, -1]])  # t down
    if rest:
        model.rest_curvatures = RNG.normal(0.0, 30.0, size=(segments, 3))
    return model


def contact_model():
    """A 10-cm strand from above a 5-cm ball, bent into it: samples deep in the penalty."""
    scene = {"strands": [{"length": 0.1, "segments": 8,
                          "root": {"position": [0, 0, 0.03], "tangent": [1, 0, 0],
                                   "normal": [0, 0, 1]}}],
             "body": {"spheres": [{"center": [0.095, 0.0, -0.015], "radius": 0.05}]}}
    return ringlet.parse_scene(scene).strands[0]


def natural(model):
    if model.rest_curvatures is not None:
        return model.rest_curvatures.reshape(-1)
    return np.tile(model.natural_curvature, model.num_segments())


def fd_gradient(model, q, step):
    g = np.empty_like(q)
    for j in range(q.size):
        e = np.zeros_like(q)
        e[j] = step
        up, down = ringlet.energy(model, q + e).total, ringlet.energy(model, q - e).total
        g[j] = (up - down) / (2 * step)
    return g


def fd_hessian(model, q, step):
    h = np.empty((q.size, q.size))
    for j in range(q.size):
        e = np.zeros_like(q)
        e[j] = step
        h[:, j] = (ringlet.gradient(model, q + e) - ringlet.gradient(model, q - e)) / (2 * step)
    return h


CASES = {
    "gravity": (lambda: curly_model(), 20.0),
    "rest shape": (lambda: curly_model(rest=True), 20.0),
    "contact": (contact_model, 0.0),
}


@pytest.mark.parametrize("case", CASES)
def test_derivatives_against_finite_differences(case):
    build, spread = CASES[case]
    model = build()
    q = natural(model) + RNG.normal(0.0, spread, size=3 * model.num_segments())
    if case == "contact":
        q = np.tile([5.0, -4.0, 3.0], 8)  # bends down into the ball
        terms = ringlet.energy(model, q)
        assert terms.contact > 0 and terms.gravity < 0 and terms.elastic > 0
    g = ringlet.gradient(model, q)
    assert g.shape == (q.size,) and g.dtype == np.float64
    # Anti-vacuity: far from an equilibrium, every term in play.
    assert np.abs(g).max() > 1e-9
    g_fd = fd_gradient(model, q, 1e-4)  # measured error 6e-11 of max|g|
    np.testing.assert_allclose(g, g_fd, rtol=0, atol=1e-8 * np.abs(g).max())
    h = ringlet.hessian(model, q)
    assert h.shape == (q.size, q.size)
    np.testing.assert_array_equal(h, h.T)
    h_fd = fd_hessian(model, q, 1e-4)
    np.testing.assert_allclose(h, h_fd, rtol=0, atol=1e-8 * np.abs(h).max())
    # (n, 3) and flat curvatures are the same configuration.
    assert np.array_equal(ringlet.gradient(model, q.reshape(-1, 3)), g)


@pytest.mark.parametrize("rest", [False, True])
def test_elastic_energy_is_eq_3(rest):
    model = curly_model(rest=rest)
    q0 = natural(model)
    assert ringlet.energy(model, q0).elastic == 0.0
    assert ringlet.energy(model, q0.reshape(-1, 3)).elastic == 0.0
    q = q0 + RNG.normal(0.0, 20.0, size=q0.size)
    # Eq. 3: E_e = sum_i 1/2 l_i (W_i - W0_i)^T K (W_i - W0_i), K = diag(E I1, E I2, mu J).
    d = (q - q0).reshape(-1, 3)
    k = np.asarray(model.stiffness())
    expected = 0.5 * np.sum(np.asarray(model.segment_lengths) * (d * d * k).sum(axis=1))
    terms = ringlet.energy(model, q)
    assert terms.elastic == pytest.approx(expected, rel=1e-14)
    assert terms.total == terms.elastic + terms.gravity + terms.contact
    assert terms.contact == 0.0


def test_gravity_energy_of_a_straight_strand():
    # Straight (q = 0), tangent t: r(s) - r(0) = s t, so E_g = -f . t L^2 / 2 (eq. 4), f = rho S g.
    t = np.array([1.0, 0.0, -1.0]) / np.sqrt(2)
    n1 = np.array([0.0, 1.0, 0.0])
    frame = np.stack([n1, np.cross(t, n1), t], axis=1)
    model = ringlet.StrandModel(ringlet.uniform_segments(0.3, 5), ringlet.CrossSection(5e-5, 4e-5),
                                root_frame=frame)
    f = np.asarray(model.weight_per_length())
    terms = ringlet.energy(model, np.zeros(15))
    assert terms.gravity == pytest.approx(-f @ t * 0.3 ** 2 / 2, rel=1e-13)
    assert terms.gravity < 0 and terms.elastic == 0.0


def test_the_gradient_vanishes_at_a_solved_equilibrium():
    model = curly_model(segments=10)
    options = ringlet.SolveOptions(tolerance=1e-10)
    (result,) = ringlet.solve(model, options)
    assert result.summary.converged()
    q = result.curvatures.reshape(-1)

    def residual(q):
        # kirchhoff.h's definition: max_i |g_i| / (l_i M_ref),
        # M_ref = |f| L^2 / 2 + max_i |K (W_i - W0_i)| + E I1 / L.
        g = ringlet.gradient(model, q).reshape(-1, 3)
        k = np.asarray(model.stiffness())
        length = model.length()
        moment = ((q - natural(model)).reshape(-1, 3) * k)
        m_ref = (np.linalg.norm(model.weight_per_length()) * length ** 2 / 2
                 + np.linalg.norm(moment, axis=1).max() + k[0] / length)
        return (np.linalg.norm(g, axis=1) / (np.asarray(model.segment_lengths) * m_ref)).max()
    assert residual(q) <= 1e-10
    assert residual(natural(model)) > 1e-3  # anti-vacuity: the rest shape is not in balance


@pytest.mark.parametrize("curvatures, message", [
    (np.zeros((5, 3)), "curvatures: expected an (n, 3) or (3n,) array of (kappa1, kappa2, tau) "
                       "per segment (1/m), n = 6 segments, got shape (5, 3)"),
    (np.zeros(17), "got shape (17,)"),
    (np.full(18, np.nan), "curvatures: expected finite numbers (1/m), got nan at segment 0"),
    (np.zeros(18, dtype=complex), "curvatures: expected an (n, 3) or (3n,) array"),
])
def test_bad_curvatures_name_the_argument(curvatures, message):
    for function in (ringlet.energy, ringlet.gradient, ringlet.hessian):
        with pytest.raises(ringlet.Error) as error:
            function(curly_model(), curvatures)
        assert message in str(error.value)


def test_dense_hessian_limit():
    model = ringlet.StrandModel(ringlet.uniform_segments(1.0, 1001),
                                ringlet.CrossSection(5e-5, 5e-5))
    q = np.zeros(3 * 1001)
    assert ringlet.gradient(model, q).shape == (3003,)
    with pytest.raises(ringlet.Error) as error:
        ringlet.hessian(model, q)
    assert str(error.value).startswith("model: the dense Hessian (3n x 3n): ")
