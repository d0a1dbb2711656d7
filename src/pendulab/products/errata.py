"""The misprints of both sources, each beside the computation that shows it.

:func:`entries` returns one dict per misprint of 000_8cba66c4fdf94ac6.txt
(``"000"``) or 002_19b336b29bb1f03b.txt (``"002"``)::

    {"source": "000", "where": "eq. 19",
     "printed": LaTeX of what the source prints,
     "found": LaTeX of what pendulab's derivation gives,
     "evidence": LaTeX/text of the computation, its numbers computed now,
     "text": {"en": one sentence, "pt": the same in Portuguese}}

LaTeX is math without ``$`` delimiters in ``printed`` and ``found``; in
``evidence`` math stands between ``$`` (it mixes words and formulas).  The
notes' errata section (:mod:`pendulab.products.notes`) typesets them.

Where a formula is at stake, ``found`` is SymPy's LaTeX of the expression the
analyses derive (:mod:`pendulab.analyses.averaging`,
:mod:`pendulab.analyses.bessel`, :mod:`pendulab.canonical`, ...), and the
numbers in ``evidence`` come from pendulab's own engines (exact Floquet limits,
certified Bessel zeros, the sweeps of 000 sec. 4) when :func:`entries` runs.
``printed`` is the source's formula as it stands, kept as a SymPy expression
too (:func:`cases` gives both expressions and a point where they differ, which
tests/test_errata.py checks against independent methods).  docs/sources.md
lists every equation of both sources and these errata.

Nothing here is a product of a scene: the ``notes`` product calls
:func:`entries` for its errata section.
"""

import functools
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Case:
    """One misprint: the entry's fields, and what the tests need to check it.

    ``printed_expr`` and ``found_expr`` are SymPy objects (an expression, an
    equation, a tuple of numbers) whose difference at ``point`` (symbol name
    -> number) shows that the printed form is not the found one; ``data``
    holds the numbers the evidence quotes (as computed).
    """

    source: str
    where: str
    printed: str
    found: str
    evidence: str
    en: str
    pt: str
    printed_expr: object = None
    found_expr: object = None
    point: dict = field(default_factory=dict)
    data: dict = field(default_factory=dict)

    def entry(self):
        """The entry dict of :func:`entries`."""
        return {"source": self.source, "where": self.where, "printed": self.printed,
                "found": self.found, "evidence": self.evidence,
                "text": {"en": self.en, "pt": self.pt}}


def entries():
    """Every misprint found in either source, as a list of dicts (module docstring)."""
    return [case.entry() for case in cases()]


@functools.lru_cache(maxsize=None)
def cases():
    """The misprints as :class:`Case` records, 000's first, each in the source's order."""
    return tuple(build() for build in _BUILDERS)


# ---------------------------------------------------------------------------
# printing helpers
# ---------------------------------------------------------------------------

def _tex(expr):
    """SymPy's LaTeX of ``expr``, with H_n for harmonic numbers and ln for log."""
    from sympy.printing.latex import LatexPrinter

    class _Printer(LatexPrinter):
        def _print_harmonic(self, e, exp=None):
            return "H_{%s}" % self._print(e.args[0])

    return _Printer({"ln_notation": True, "inv_trig_style": "full"}).doprint(expr)


def _num(x, digits=6):
    """A number as text with ``digits`` significant digits."""
    import mpmath
    return mpmath.nstr(mpmath.mpf(x), digits)


def _dot_symbols():
    import sympy as sp
    return {"theta": sp.Symbol(r"\theta"), "dtheta": sp.Symbol(r"\dot{\theta}"),
            "ddtheta": sp.Symbol(r"\ddot{\theta}"), "y0": sp.Symbol("y_0"),
            "dy0": sp.Symbol(r"\dot{y}_0"), "ddy0": sp.Symbol(r"\ddot{y}_0"),
            "tau_i": sp.Symbol(r"\tau_i"), "avg_tau_i": sp.Symbol(r"\langle\tau_i\rangle"),
            "psi_M": sp.Symbol(r"\psi_M")}


def _in_time(expr, theta, drive=None):
    """``expr`` with theta(t), its derivatives (and the drive's) as dotted symbols."""
    from pendulab import symbols as S
    d = _dot_symbols()
    rep = {theta.diff(S.t, 2): d["ddtheta"], theta.diff(S.t): d["dtheta"]}
    if drive is not None:
        rep.update({drive.diff(S.t, 2): d["ddy0"], drive.diff(S.t): d["dy0"]})
    out = expr.subs(rep).subs(theta, d["theta"])
    return out.subs(drive, d["y0"]) if drive is not None else out


def _physical(expr):
    """An expression in the dimensionless groups written back in m, l, I, a, omega0, omega."""
    from pendulab import symbols as S
    return expr.subs({S.inertia_ratio: S.I / (S.m * S.l**2), S.w0_over_w: S.omega0 / S.omega,
                      S.a_over_l: S.a / S.l})


# ---------------------------------------------------------------------------
# 000_8cba66c4fdf94ac6.txt
# ---------------------------------------------------------------------------

def _lagrangian():
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.equations import derive
    from pendulab.systems import DrivenPivot

    system = DrivenPivot(body="explicit")
    th, y0 = system.coordinate, system.DRIVE
    template = system.lagrangian_template()
    dth = th.diff(S.t)
    cross = sp.Add(*[term for term in sp.Add.make_args(template) if term.has(dth) and term.has(y0)])
    d = _dot_symbols()
    found = _in_time(cross, th, y0)
    printed = -S.m * S.l * d["dtheta"] * d["y0"] * sp.sin(d["theta"])  # 000, the Lagrangian
    # the Euler-Lagrange expression of each Lagrangian, d/dt dL/dtheta' - dL/dtheta
    def euler_lagrange(lag):
        return sp.expand(sp.diff(lag, dth).diff(S.t) - sp.diff(lag, th))
    el_found = euler_lagrange(template)
    wrong = template - cross + (-S.m * S.l * dth * y0 * sp.sin(th))
    el_printed = euler_lagrange(wrong)
    derived = derive(system).euler_lagrange  # the equations stage (drive a cos(omega t))
    same = sp.expand(el_found.subs(y0, system.drive).doit() - derived) == 0
    evidence = (f"Euler--Lagrange with pendulab's term: ${_tex(_in_time(el_found, th, y0))} = 0$ "
                f"(the equation the source states{'' if same else ' [differs from the equations stage]'}); "
                f"with the printed term: ${_tex(_in_time(el_printed, th, y0))} = 0$, "
                r"a velocity beside $g$.")
    return Case("000", "after eq. 2, the Lagrangian", _tex(printed), _tex(found), evidence,
                "The cross term of the Lagrangian needs the pivot's velocity, not its position.",
                "O termo cruzado da Lagrangiana precisa da velocidade do pivô, não da sua posição.",
                printed, found,
                point={"m": 1.0, "l": 0.5, r"\dot{\theta}": 0.7, r"\theta": 0.3, "y_0": 0.02,
                       r"\dot{y}_0": -1.3},
                data={"euler_lagrange_matches_stage": same})


def _eq13():
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses import averaging

    found = averaging.fast_displacement("I")
    rod = averaging.fast_displacement("rod")
    printed = -(S.a / S.l) * sp.sin(S.psi) * sp.cos(S.omega * S.t)  # 000 eq. 13 as printed
    ratio = sp.simplify(rod / printed)
    evidence = (r"the zero-mean periodic solution of $I\ddot\delta = \tau_i(\psi)$; for the rod "
                rf"($I = \tfrac43 m l^2$) $\delta = {_tex(rod)}$, ${_tex(ratio)}$ times the printed one.")
    return Case("000", "eq. 13", r"\delta = " + _tex(printed), r"\delta = " + _tex(found), evidence,
                r"The fast deviation has the amplitude $(m l^2/I)(a/l)$ and the sign of the drive's "
                r"torque; the printed $a/l$ is a point mass's amplitude, with the opposite sign.",
                r"O desvio rápido tem amplitude $(m l^2/I)(a/l)$ e o sinal do torque do forçamento; o "
                r"$a/l$ impresso é a amplitude de uma massa pontual, com o sinal oposto.",
                printed, found,
                point={"a": 0.01, "l": 0.5, "m": 1.0, "I": 1 / 3, "psi": 0.3, "omega": 20.0, "t": 0.1},
                data={"rod_over_printed": ratio})


def _torques():
    """(inertial, gravitational) torques on theta from the derived equation I theta'' = ..."""
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.equations import derive
    from pendulab.systems import DrivenPivot

    system = DrivenPivot(body="explicit")
    th = system.coordinate
    el = sp.expand(derive(system).euler_lagrange)
    acc = th.diff(S.t, 2)
    torque = sp.expand(-(el - el.coeff(acc) * acc))
    gravitational = torque.coeff(S.g) * S.g
    return (sp.expand(torque - gravitational), gravitational, el.coeff(acc), th)


def _eq14():
    import sympy as sp

    from pendulab import symbols as S

    inertial, gravitational, inertia, th = _torques()
    d = _dot_symbols()
    found = inertial.subs(th, d["theta"])
    printed = S.m * S.a * S.l * S.omega**2 * sp.sin(d["theta"]) * sp.cos(S.omega * S.t)  # 000 eq. 14
    grav = gravitational.subs(th, d["theta"])
    evidence = (rf"pendulab's equation of motion: ${_tex(inertia)}\,\ddot\theta = {_tex(found)} + "
                rf"{_tex(grav)}$; the gravitational part is the source's $\tau_g$, so $\tau_i$ counted "
                r"the same way (where $\theta$ grows) has the sign found.")
    return Case("000", "eq. 14", r"\tau_i = " + _tex(printed), r"\tau_i = " + _tex(found), evidence,
                "The inertial torque, counted in the sense in which the gravitational torque is, "
                "has the opposite sign; it cancels against the sign of eq.~13 in the average.",
                "O torque inercial, contado no mesmo sentido do torque gravitacional, tem o sinal "
                "oposto; ele se cancela com o sinal da eq.~13 na média.",
                printed, found,
                point={"m": 1.0, "a": 0.01, "l": 0.5, "omega": 20.0, r"\theta": 0.3, "t": 0.1})


def _eq16():
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses import averaging

    found = averaging.averaged_torques("I")["inertial"]
    rod = averaging.averaged_torques("rod")["inertial"]
    printed = -S.m * S.a**2 * S.omega**2 / 4 * sp.sin(2 * S.psi)  # 000 eq. 16
    u_eff = averaging.effective_potential()
    kapitza = -sp.diff(u_eff, S.psi) - averaging.averaged_torques("I")["gravitational"]
    agree = sp.simplify(sp.expand_trig(kapitza - found)) == 0
    evidence = (rf"averaging with the derived $\delta$; Kapitza's potential $U_{{\rm eff}} = {_tex(u_eff)}$ "
                rf"gives the same torque{'' if agree else ' [it does not]'}; for the rod "
                rf"$\langle\tau_i\rangle = {_tex(rod)}$, $\tfrac34$ of the printed one.")
    return Case("000", "eq. 16", r"\langle\tau_i\rangle = " + _tex(printed),
                r"\langle\tau_i\rangle = " + _tex(found), evidence,
                r"The averaged inertial torque carries $m l^2/I$ (from eq.~13's amplitude); as printed "
                r"it holds for a point mass only, and so does the averaged potential after it.",
                r"O torque inercial médio carrega $m l^2/I$ (da amplitude da eq.~13); como impresso, "
                r"vale só para uma massa pontual, assim como o potencial médio que o segue.",
                printed, found,
                point={"m": 1.0, "a": 0.01, "l": 0.5, "omega": 20.0, "I": 1 / 3, "psi": 0.3},
                data={"kapitza_agrees": agree})


#: 000 sec. 2.3: the point where the evidence of eq. 19 and psi_M quotes numbers (a rod).
ROD_RATIO = "4/3"
EQ19_W0_OVER_W = "0.05"
PSI_M_A_OVER_L = "0.2"


def _eq19():
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses import averaging
    from pendulab.analyses.phelps_hunter import lower_limit_small_ratio
    from pendulab.analyses.stability import limits

    found_rhs = averaging.lower_bound_physical()
    printed_rhs = sp.sqrt(2) * sp.sqrt(S.inertia_ratio) * S.w0_over_w  # 000 eq. 19 as printed
    r, rho = sp.Rational(ROD_RATIO), sp.Rational(EQ19_W0_OVER_W)
    rf_ = float(r)
    exact = limits(float(rho), rf_, "exact")[0]
    values = {"exact": exact, "printed": float(printed_rhs.subs({S.inertia_ratio: r, S.w0_over_w: rho})),
              "found": float(found_rhs.subs({S.inertia_ratio: r, S.w0_over_w: rho}))}
    series = lower_limit_small_ratio()
    lead = sp.Poly(series, S.w0_over_w).terms()[-1]  # the lowest power of omega0/omega
    lead_term = lead[1] * S.w0_over_w**lead[0][0]
    evidence = (rf"rod, $\omega_0/\omega = {EQ19_W0_OVER_W}$: exact Floquet lower limit "
                rf"$a/l = {_num(values['exact'])}$, printed {_num(values['printed'])}, "
                rf"found {_num(values['found'])}; the exact limit's series begins "
                rf"${_tex(_physical(lead_term))}$.")
    al = S.a / S.l
    return Case("000", "eq. 19", _tex(sp.StrictGreaterThan(al, _physical(printed_rhs), evaluate=False)),
                _tex(sp.StrictGreaterThan(al, _physical(found_rhs), evaluate=False)), evidence,
                r"Butikov's lower bound carries $I/(m l^2)$, not its square root; the two agree only "
                "for a point mass, and for the rod the exact Floquet limit sides with the found form.",
                r"O limite inferior de Butikov carrega $I/(m l^2)$, não a sua raiz quadrada; as duas "
                "formas coincidem só para a massa pontual, e para a barra o limite exato de Floquet "
                "confirma a forma encontrada.",
                printed_rhs, found_rhs,
                point={"inertia_ratio": rf_, "w0_over_w": float(rho)},
                data=dict(values, leading_term=lead_term))


def _psi_m():
    import mpmath
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses import averaging

    found = averaging.psi_M_physical()
    printed = sp.acos(2 * S.inertia_ratio * S.w0_over_w**2 / S.a_over_l**2)  # 000, after eq. 19
    r, rho, al = sp.Rational(ROD_RATIO), sp.Rational(EQ19_W0_OVER_W), sp.Rational(PSI_M_A_OVER_L)
    at = {S.inertia_ratio: r, S.w0_over_w: rho, S.a_over_l: al}
    # Kapitza's potential for the rod (l = m = 1, omega = 1): its maximum away from psi = 0
    u = averaging.effective_potential()
    u = u.subs({S.I: r, S.m: 1, S.l: 1, S.omega: 1, S.a: al, S.g: r * rho**2})  # g = I omega0^2/(m l)
    du = sp.lambdify(S.psi, sp.diff(u, S.psi), "mpmath")
    deg = 180 / mpmath.pi
    with mpmath.workdps(30):
        guess = mpmath.mpf(float(found.subs(at)))
        peak = mpmath.findroot(du, guess)
        values = {"printed": float(printed.subs(at)) * float(deg), "found": float(found.subs(at)) * float(deg),
                  "kapitza": float(peak * deg)}
    evidence = (rf"rod, $a/l = {PSI_M_A_OVER_L}$, $\omega_0/\omega = {EQ19_W0_OVER_W}$: printed "
                rf"$\psi_M = {_num(values['printed'], 5)}^\circ$, found {_num(values['found'], 5)}$^\circ$, "
                rf"maximum of Kapitza's $U_{{\rm eff}}$ at {_num(values['kapitza'], 5)}$^\circ$.")
    return Case("000", r"after eq. 19, $\psi_M$", r"\psi_M = " + _tex(_physical(printed)),
                r"\psi_M = " + _tex(_physical(found)), evidence,
                r"The angle of unstable equilibrium carries $(I/(m l^2))^2$, for the same reason as eq.~19.",
                r"O ângulo de equilíbrio instável carrega $(I/(m l^2))^2$, pela mesma razão da eq.~19.",
                printed, found,
                point={"inertia_ratio": float(r), "w0_over_w": float(rho), "a_over_l": float(al)},
                data=values)


#: Fig. 3's initial conditions (theta(0), theta'(0)): as its caption gives them, as the text does.
FIG3_CAPTION = ("0.01", "0.06")
FIG3_TEXT = ("0.06", "0.01")


def _fig3():
    import sympy as sp

    from pendulab.numerics import sweep as S

    initial = [tuple(float(x) for x in FIG3_TEXT), tuple(float(x) for x in FIG3_CAPTION)]
    spec = S.make_spec(S.SystemSpec("rod"), grid=10, initial=initial, criterion="mean")
    res = S.sweep(spec, executor="serial", quiet=True)
    counts = [int(c) for c in S.verdict("mean", res.stats).reshape(len(initial), -1).sum(axis=1)]
    evidence = (r"stable pairs on the $10\times10$ grid of sec.~4 (rod, $|\langle\theta\rangle| < 0.1$ "
                rf"over 300 drive periods, RK4): {counts[0]} at $({', '.join(FIG3_TEXT)})$, the count "
                rf"the text gives for Fig.~3's initial condition (14), and {counts[1]} at "
                rf"$({', '.join(FIG3_CAPTION)})$.")
    pair = r"\left(\theta(0), \dot\theta(0)\right) = "
    printed = sp.Tuple(*[sp.Float(x) for x in FIG3_CAPTION])
    found = sp.Tuple(*[sp.Float(x) for x in FIG3_TEXT])
    return Case("000", "sec. 4, Fig. 3 caption", pair + "(" + ", ".join(FIG3_CAPTION) + ")",
                pair + "(" + ", ".join(FIG3_TEXT) + ")", evidence,
                "The caption of Fig.~3 swaps the initial angle and angular velocity that the text "
                "gives for that figure.",
                "A legenda da Fig.~3 troca o ângulo e a velocidade angular iniciais que o texto dá "
                "para essa figura.",
                printed, found, data={"counts": dict(zip(("text", "caption"), counts))})


# ---------------------------------------------------------------------------
# 002_19b336b29bb1f03b.txt
# ---------------------------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _string():
    """(system, equations, Bessel form, closed form) of the variable-length pendulum."""
    from pendulab.analyses.bessel import closed_form
    from pendulab.canonical import length_form
    from pendulab.equations import derive
    from pendulab.systems import VariableLength

    system = VariableLength()
    eqs = derive(system)
    form = length_form(eqs)
    return system, eqs, form, closed_form(form, system.length)


def _l_symbols(expr):
    import sympy as sp

    from pendulab import symbols as S
    th = S.theta(S.Lvar)
    return expr.subs({th.diff(S.Lvar, 2): sp.Symbol(r"\theta_{LL}"), th.diff(S.Lvar): sp.Symbol(r"\theta_L")}
                     ).subs(th, sp.Symbol(r"\theta"))


def _references():
    import sympy as sp

    from pendulab import symbols as S
    system, eqs, form, _ = _string()
    length = S.L(S.t)
    linear = _in_time(eqs.linear.subs(length.diff(S.t), sp.Symbol(r"\dot{L}")), system.coordinate, None)
    linear = linear.subs(length, sp.Symbol("L"))
    line = _l_symbols(form.length_equation)
    evidence = (rf"eq.~4, ${_tex(linear)} = 0$, with eqs.~5--6 ($d/dt = v_0\,d/dL$) gives "
                rf"${_tex(line)} = 0$, the line the source then prints; eqs.~1--3 are the "
                r"accelerations, Newton's law and its nonlinear result.")
    return Case("002", "before eqs. 5 and 7, equation numbers",
                r"\text{solve (1); substitute (2), (3) in (1)}",
                r"\text{solve (4); substitute (5), (6) in (4)}", evidence,
                "The solution section cites eqs.~1--3 where it uses eq.~4 (the linear equation) and "
                "eqs.~5--6 (the chain rule).",
                "A seção de resolução cita as eqs.~1--3 onde usa a eq.~4 (a equação linear) e as "
                "eqs.~5--6 (a regra da cadeia).",
                sp.Tuple(2, 3, 1), sp.Tuple(5, 6, 4), data={"length_equation": form.length_equation})


def _eq7():
    import sympy as sp

    from pendulab import symbols as S
    _, _, form, sol = _string()
    found = _l_symbols(form.euler_form)
    L, th_ll, th_l, th = sp.Symbol("L"), sp.Symbol(r"\theta_{LL}"), sp.Symbol(r"\theta_L"), sp.Symbol(r"\theta")
    found = found.subs(S.Lvar, L)
    printed = L**2 * th_ll + 2 * L * th_l + S.g / S.v0**2 * th  # 002 eq. 7 as printed
    evidence = (rf"the line before eq.~7 times $L/v_0^2$; $\theta = {_tex(sol.general_z)}$, "
                rf"$z = {_tex(sol.z_of_L)}$, leaves the residual "
                rf"{_tex(sol.residual_L)} in the found form, which is what the Bessel match "
                rf"($\alpha = {_tex(form.alpha)}$, $\beta = {_tex(form.beta)}$, $k = {_tex(form.k)}$, "
                rf"$p = {_tex(form.p)}$) fits.")
    return Case("002", "eq. 7", _tex(printed) + " = 0", _tex(found) + " = 0", evidence,
                "Eq.~7 drops a factor $L$ in its last term; the Bessel solution satisfies the "
                r"equation with $g L/v_0^2$.",
                "A eq.~7 perde um fator $L$ no último termo; a solução de Bessel satisfaz a equação "
                r"com $g L/v_0^2$.",
                printed, found, point={"L": 2.0, r"\theta_{LL}": 0.3, r"\theta_L": -0.2,
                                       r"\theta": 0.5, "g": 9.81, "v0": 0.5},
                data={"residual_L": sol.residual_L})


def _y1_parts():
    """The pieces of the series of Y_1 that 002 prints: (log term, -1/z - z/4, the sum)."""
    import sympy as sp

    from pendulab import symbols as S
    n = sp.Symbol("n", integer=True, positive=True)
    z = S.z
    total = sp.Sum((-1)**(n - 1) * (sp.harmonic(n) + sp.harmonic(n + 1))
                   / (sp.factorial(n) * sp.factorial(n + 1)) * (z / 2)**(2 * n + 1), (n, 1, sp.oo))
    return (sp.log(z / 2) + sp.EulerGamma) * sp.besselj(1, z), -1 / z - z / 4, total


def _y1_series(half):
    """Y_1(z) as 002 prints its series (``half`` False) or with the sum halved (DLMF 10.8.1)."""
    import sympy as sp
    log_term, poles, total = _y1_parts()
    return 2 / sp.pi * (log_term + poles + (sp.Rational(1, 2) if half else 1) * total)


def _y1_tex(half):
    """:func:`_y1_series` typeset in the source's order, the bracket kept."""
    log_term, _, total = _y1_parts()
    return (r"Y_1(z) = \frac{2}{\pi}\left[" + _tex(log_term) + r" - \frac{1}{z} - \frac{z}{4} + "
            + (r"\frac{1}{2}" if half else "") + _tex(total) + r"\right]")


#: 002 "Demonstração": the z where the evidence sums the series of Y_1.
Y1_Z = 2


def _y1():
    import mpmath
    import sympy as sp
    from flint import arb, ctx

    from pendulab import symbols as S
    printed, found = _y1_series(False), _y1_series(True)
    with mpmath.workdps(25):
        values = {"printed": sp.N(printed.subs(S.z, Y1_Z), 20), "found": sp.N(found.subs(S.z, Y1_Z), 20)}
    old = ctx.prec
    try:
        ctx.prec = 80
        ball = arb(Y1_Z).bessel_y(1)
        y1 = ball.mid().str(12, radius=False)
        contains = ball.overlaps(arb(str(values["found"]), 1e-15)) and not ball.overlaps(
            arb(str(values["printed"]), 1e-15))
    finally:
        ctx.prec = old
    evidence = (rf"summed at $z = {Y1_Z}$: printed series {_num(values['printed'])}, with the sum halved "
                rf"{_num(values['found'])}; $Y_1({Y1_Z}) = {_num(y1)}$ (arb ball, python-flint)"
                f"{'' if contains else ' [the ball does not decide]'}; the limit $D = 2/\\pi$ "
                r"uses only the terms $-1/z$ and $J_1$, so it is not affected.")
    return Case("002", "Demonstração, series of $Y_1$", _y1_tex(False), _y1_tex(True), evidence,
                r"The series of $Y_1$ lacks the factor $\tfrac12$ in front of its sum (DLMF 10.8.1).",
                r"A série de $Y_1$ perde o fator $\tfrac12$ diante do seu somatório (DLMF 10.8.1).",
                printed, found, point={"z": float(Y1_Z)},
                data={"printed": values["printed"], "found": values["found"], "Y1": y1,
                      "ball_decides": contains})


def _constant_b():
    import sympy as sp

    from pendulab import symbols as S
    _, _, _, sol = _string()
    found = sol.constants[S.B]
    printed = -sp.pi / 2 * S.theta_0 * S.z0**2 * sp.besselj(2, S.z0)  # 002 "Consequência"
    cramer = sol.cramer[S.B]
    evidence = (rf"Cramer's rule gives $B = {_tex(cramer)}$, and with "
                rf"$J_1 Y_2 - J_2 Y_1 = {_tex(sol.cross)}$ (proved by SymPy) $B = {_tex(found)}$.")
    return Case("002", "Consequência, $B$", "B = " + _tex(printed), "B = " + _tex(found), evidence,
                r"With the cross product $-2/(\pi z_0)$, Cramer's rule gives $B$ with a plus sign.",
                r"Com o produto cruzado $-2/(\pi z_0)$, a regra de Cramer dá $B$ com sinal positivo.",
                printed, found, point={"theta_0": 0.1, "z0": 3.0})


def _theta_z():
    import mpmath
    import sympy as sp

    from pendulab import symbols as S
    _, _, _, sol = _string()
    found = sol.particular_z
    printed = (sp.pi / 2 * S.theta_0 * S.z0**2 * S.z  # 002 "Consequência"
               * (-sp.bessely(2, S.z0) * sp.besselj(1, S.z) + sp.besselj(2, S.z0) * sp.bessely(1, S.z)))
    z0 = 3
    with mpmath.workdps(25):
        at_found = sp.N(found.subs({S.z: z0, S.z0: z0, S.theta_0: 1}), 15)
        at_printed = sp.N(printed.subs({S.z: z0, S.z0: z0, S.theta_0: 1}), 15)
    evidence = (rf"at $z = z_0 = {z0}$ the found form gives $\theta = {_num(at_found)}\,\theta_0$ "
                rf"(the initial condition), the printed one ${_num(at_printed)}\,\theta_0 = z_0^2\theta_0$.")
    return Case("002", r"Consequência, $\theta(z)$", r"\theta = " + _tex(printed), r"\theta = " + _tex(found),
                evidence,
                "The solution carries $z^{-1}$, not $z$, as the general solution does; the same slip "
                "repeats in the case $B = 0$.",
                "A solução carrega $z^{-1}$, não $z$, como a solução geral; o mesmo deslize se repete "
                "no caso $B = 0$.",
                printed, found, point={"z": 4.0, "z0": 3.0, "theta_0": 0.1},
                data={"at_found": at_found, "at_printed": at_printed})


def _constant_c():
    import sympy as sp

    from pendulab import symbols as S
    system, _, _, sol = _string()
    theta_b0 = sol.particular_z.subs(sp.besselj(2, S.z0), 0)
    z_t = sol.z_of_L.subs(S.Lvar, system.length)
    # theta(t) = -C (L0 + v0 t)^(-1/2) J1(z(t)): C = -theta sqrt(L) / J1(z), cancelled as a
    # rational function of the square roots (no simplify: it would rewrite Y2 through Y1, Y0)
    c_found = sp.cancel(-(theta_b0.subs(S.z, z_t)) * sp.sqrt(system.length) / sp.besselj(1, z_t))
    if c_found.has(S.t):  # pragma: no cover - the closed form's z^-1 cancels sqrt(L)
        raise RuntimeError(f"C depends on t: {c_found}")
    c_found = sp.factor(c_found.subs(S.z0, sol.z0))
    printed = (sp.pi / 2 * 4 * S.g * S.L0 / S.v0**2 * S.theta_0  # 002 "Consequência", C
               * sp.bessely(2, 2 / S.v0 * sp.sqrt(S.g * S.L0)))
    ratio = sp.factor(sp.cancel(c_found / printed))
    evidence = (r"the found $\theta(z)$ with $J_2(z_0) = 0$ written in $t$: "
                rf"$\theta = {_tex(theta_b0)}$, $z = {_tex(z_t)}$; found over printed $C$: "
                rf"${_tex(ratio)}$.")
    return Case("002", "Consequência, $C$", "C = " + _tex(printed), "C = " + _tex(c_found), evidence,
                r"The constant $C$ lacks the factor $v_0/(2\sqrt g)$ that $z^{-1}$ brings in.",
                r"A constante $C$ perde o fator $v_0/(2\sqrt g)$ que $z^{-1}$ introduz.",
                printed, c_found, point={"g": 9.81, "L0": 0.5, "v0": 0.05, "theta_0": 0.1},
                data={"found_over_printed": ratio})


def _item1():
    import mpmath
    import sympy as sp

    from pendulab import symbols as S
    from pendulab.analyses.bessel_zeros import bessel_zeros
    _, _, _, sol = _string()
    theta = sp.lambdify((S.z, S.z0, S.theta_0), sol.particular_z, "mpmath")
    with mpmath.workdps(30):
        j1 = [mpmath.mpf(s) for s in bessel_zeros(1, 2, 30).strings]
        j2 = [mpmath.mpf(s) for s in bessel_zeros(2, 2, 30).strings]
        at_j2 = theta(j2[1], j2[0], 1)
        at_j1 = theta(j1[1], j2[0], 1)
    evidence = (r"with $z_0 = j_{2,1}$ ($B = 0$): at $z = j_{2,2}$, where $d\theta/dz = 0$, "
                rf"$\theta = {_num(at_j2)}\,\theta_0$; at $z = j_{{1,2}}$, $|\theta| < 10^{{-25}}\theta_0$"
                f"{'' if abs(at_j1) < 1e-25 else ' [not]'}.")
    return Case("002", "item 1", r"\theta = 0 \text{ where } \frac{d\theta}{dz} = 0",
                r"\theta = 0 \text{ where } J_1(z) = 0", evidence,
                r"The pendulum passes $\theta = 0$ where $J_1(z)$ vanishes; $d\theta/dz = 0$ marks its "
                "turning points (item 2).",
                r"O pêndulo passa por $\theta = 0$ onde $J_1(z)$ se anula; $d\theta/dz = 0$ marca os "
                "pontos de retorno (item 2).",
                data={"theta_at_j22": at_j2, "theta_at_j12": at_j1})


def _figure_caption():
    import sympy as sp

    from pendulab.analyses.bessel_zeros import ball_digits, bessel_zeros
    j0, j1, j2 = (bessel_zeros(n, 2, 12).balls for n in (0, 1, 2))
    caption = ball_digits(j0[1] ** 2 - j1[0] ** 2, 6)
    text = ball_digits(j1[1] ** 2 - j2[0] ** 2, 6)
    evidence = (rf"certified zeros: $j_{{1,2}}^2 - j_{{2,1}}^2 = {text}$, the table's first quarter period "
                rf"(22.8438); with $J_0, J_1$ the same step gives $j_{{0,2}}^2 - j_{{1,1}}^2 = {caption}$.")
    x = sp.Symbol("x")
    return Case("002", "Figure 1 caption", r"J_0(\sqrt{x}),\ J_1(\sqrt{x})", r"J_1(\sqrt{x}),\ J_2(\sqrt{x})",
                evidence,
                "The figure caption names $J_0$ and $J_1$, while the text and the table use $J_1$ and $J_2$.",
                "A legenda da figura nomeia $J_0$ e $J_1$, enquanto o texto e a tabela usam $J_1$ e $J_2$.",
                sp.Tuple(sp.besselj(0, sp.sqrt(x)), sp.besselj(1, sp.sqrt(x))),
                sp.Tuple(sp.besselj(1, sp.sqrt(x)), sp.besselj(2, sp.sqrt(x))), point={"x": 30.0},
                data={"caption": caption, "text": text})


def _time_unit():
    import sympy as sp

    from pendulab import symbols as S
    system, _, _, sol = _string()
    z_t = sol.z_of_L.subs(S.Lvar, system.length)
    rate = sp.simplify(sp.diff(z_t**2, S.t))
    evidence = (rf"$z^2 = {_tex(sp.expand(z_t**2))}$, so $d(z^2)/dt = {_tex(rate)}$ and "
                rf"$\Delta t = {_tex(1 / rate)}\,\Delta(z^2)$: $v_0/(4g)$ is (m/s)/(m/s$^2$) = s.")
    return Case("002", "quarter periods, the unit", r"\tfrac{v_0}{4g}\ \text{as a unit of length}",
                r"\tfrac{v_0}{4g}\ \text{as a unit of time}", evidence,
                "The quarter periods are measured in the time unit $v_0/(4g)$, which the text first "
                "calls a unit of length.",
                "Os quartos de período são medidos na unidade de tempo $v_0/(4g)$, que o texto chama "
                "primeiro de unidade de comprimento.",
                data={"time_per_z2": 1 / rate})


_BUILDERS = (_lagrangian, _eq13, _eq14, _eq16, _eq19, _psi_m, _fig3,
             _references, _eq7, _y1, _constant_b, _theta_z, _constant_c, _item1, _figure_caption,
             _time_unit)
