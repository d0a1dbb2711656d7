"""The symbols of the two source documents, shared by every stage.

Names follow the sources so that users recognise them in JSON and LaTeX:

* driven pivot (000_8cba66c4fdf94ac6.txt): ``t, a, omega, omega0, g, m, l, I``,
  the angle ``theta(t)``, the Mathieu parameters ``theta0, theta1`` (000 eqs. 5-6)
  and the dimensionless time ``tau`` (000, before eq. 5);
* perturbation series (000 sec. 3): ``nu``;
* variable length (002_19b336b29bb1f03b.txt): ``L0, v0, z`` and the initial
  angle ``theta_0`` (the source writes theta0 for it; we keep it apart from the
  Mathieu parameter ``theta0``).

All physical constants are declared positive, which is what they are and what
lets SymPy simplify square roots.
"""

import sympy as sp

t = sp.Symbol("t", real=True)
tau = sp.Symbol("tau", real=True)

a = sp.Symbol("a", positive=True)
omega = sp.Symbol("omega", positive=True)
omega0 = sp.Symbol("omega0", positive=True)
g = sp.Symbol("g", positive=True)
m = sp.Symbol("m", positive=True)
l = sp.Symbol("l", positive=True)  # noqa: E741  (the source's name)
I = sp.Symbol("I", positive=True)  # noqa: E741  moment of inertia about the pivot
I0 = sp.Symbol("I0", positive=True)  # moment of inertia about the centre of mass

theta0 = sp.Symbol("theta0", real=True)
theta1 = sp.Symbol("theta1", real=True)
nu = sp.Symbol("nu", real=True)
q = sp.Symbol("q", real=True)

L0 = sp.Symbol("L0", positive=True)
v0 = sp.Symbol("v0", positive=True)
z = sp.Symbol("z", positive=True)
theta_0 = sp.Symbol("theta_0", real=True)  # initial angle of 002
Lvar = sp.Symbol("L", positive=True)  # the length as independent variable (002 eqs. 5-7)
z0 = sp.Symbol("z0", positive=True)  # z at t = 0 (002)
A = sp.Symbol("A")
B = sp.Symbol("B")

#: Floquet exponent lambda of 000 eq. 8 ("lambda" is a Python keyword, so "lam").
lam = sp.Symbol("lam", real=True)
#: The dimensionless groups in which the source states its limits (000 eqs. 12, 19, 28).
a_over_l = sp.Symbol("a_over_l", positive=True)
w0_over_w = sp.Symbol("w0_over_w", nonnegative=True)
inertia_ratio = sp.Symbol("inertia_ratio", positive=True)
#: Butikov's slow angle and fast deviation (000 eq. 13).
psi = sp.Symbol("psi", real=True)
delta = sp.Symbol("delta", real=True)

theta = sp.Function("theta", real=True)
L = sp.Function("L", positive=True)

#: Every name a JSON expression of pendulab may contain, mapped to its object.
#: ``load_expr`` uses this so that I, E, S, N, O, Q, beta, gamma ... are the
#: user's symbols, never SymPy's constants.
NAMESPACE = {
    s.name: s
    for s in (t, tau, a, omega, omega0, g, m, l, I, I0, theta0, theta1, nu, q,
              L0, v0, z, theta_0, A, B, Lvar, z0, lam, a_over_l, w0_over_w,
              inertia_ratio, psi, delta)
}
