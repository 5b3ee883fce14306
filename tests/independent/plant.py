# Independent plant model for testing `lashid diagnose`: curved borders, the switch (2.3) and backlash (2.4)
# operators of Giri et al. (Automatica), a stable A(q^-1) y = B(q^-1) u, and random draws of all of them.
# Written from the paper (sections 2-4) and docs/data-format.md only, WITHOUT reading the project's own
# generator (host_sim/sim, host_sim/plant) or its documentation. Pure Python 3, standard library only.
import cmath
import math

# ---------------------------------------------------------------- border families
# Each family returns a function g(x) of the normalised input x = (v - v_min) / (v_max - v_min), defined for
# every real x (the backlash evaluates it a little outside [0, 1]), roughly spanning [0, 1] over [0, 1].


def _lagrange(xs, ys):
    def g(x):
        total = 0.0
        for j, (xj, yj) in enumerate(zip(xs, ys)):
            term = yj
            for i, xi in enumerate(xs):
                if i != j:
                    term *= (x - xi) / (xj - xi)
            total += term
        return total
    return g


def _catmull_rom(xs, ys):
    """Cubic Catmull-Rom spline through knots at increasing xs; linear extrapolation outside."""
    k = len(xs)
    slopes = []
    for i in range(k):
        lo, hi = max(i - 1, 0), min(i + 1, k - 1)
        slopes.append((ys[hi] - ys[lo]) / (xs[hi] - xs[lo]))

    def g(x):
        if x <= xs[0]:
            return ys[0] + slopes[0] * (x - xs[0])
        if x >= xs[-1]:
            return ys[-1] + slopes[-1] * (x - xs[-1])
        i = min(int((x - xs[0]) / (xs[1] - xs[0])), k - 2)
        h = xs[i + 1] - xs[i]
        s = (x - xs[i]) / h
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        return h00 * ys[i] + h10 * h * slopes[i] + h01 * ys[i + 1] + h11 * h * slopes[i + 1]
    return g


def draw_family(rng, monotone_bias):
    """A random curved shape g(x) and its description. monotone_bias in [0, 1]: how strongly increasing."""
    fam = rng.choice(["cubic", "saturation", "exponential", "logistic_steps", "gaussian_bumps", "spline"])
    wiggle = 0.35 * (1.0 - monotone_bias) + 0.05
    if fam == "cubic":
        xs = [0.0, 1 / 3, 2 / 3, 1.0]
        ys = [x + rng.gauss(0.0, wiggle) for x in xs]
        g, p = _lagrange(xs, ys), {"knots_x": xs, "knots_y": ys}
    elif fam == "saturation":
        k, x0, lin = rng.uniform(2.0, 7.0), rng.uniform(0.25, 0.75), rng.uniform(0.0, 0.4)
        g = lambda x, k=k, x0=x0, lin=lin: 0.5 + 0.5 * math.tanh(k * (x - x0)) + lin * x
        p = {"k": k, "x0": x0, "linear": lin}
    elif fam == "exponential":
        k = rng.choice([-1, 1]) * rng.uniform(1.0, 4.0)
        g = lambda x, k=k: (1.0 - math.exp(-k * x)) / (1.0 - math.exp(-k))
        p = {"k": k}
    elif fam == "logistic_steps":
        steps = [(rng.uniform(0.1, 0.9), rng.uniform(0.2, 1.0) * (1 if rng.random() < 0.85 + 0.15 * monotone_bias
                                                                    else -0.5), rng.uniform(8.0, 25.0))
                 for _ in range(rng.randint(2, 3))]
        lin = rng.uniform(0.1, 0.5)
        g = lambda x, s=steps, lin=lin: lin * x + sum(h / (1.0 + math.exp(-k * (x - c))) for c, h, k in s)
        p = {"steps_center_height_sharpness": steps, "linear": lin}
    elif fam == "gaussian_bumps":
        bumps = [(rng.uniform(0.0, 1.0), rng.gauss(0.0, 2 * wiggle), rng.uniform(0.08, 0.25))
                 for _ in range(rng.randint(2, 4))]
        g = lambda x, b=bumps: x + sum(h * math.exp(-0.5 * ((x - c) / w) ** 2) for c, h, w in b)
        p = {"bumps_center_height_width": bumps}
    else:
        k = rng.randint(5, 7)
        xs = [i / (k - 1) for i in range(k)]
        ys = [x + rng.gauss(0.0, wiggle) for x in xs]
        g, p = _catmull_rom(xs, ys), {"knots_x": xs, "knots_y": ys}
    p["family"] = fam
    return g, p


# ---------------------------------------------------------------- operators


class Borders:
    """C_a, C_d on [v_min, v_max], with the monotone pieces used to find the roots C(x) = u of (2.4)."""

    GRID = 2000

    def __init__(self, ca, cd, v_min, v_max):
        self.ca, self.cd, self.v_min, self.v_max = ca, cd, v_min, v_max
        self.pieces = {"a": self._pieces(ca), "d": self._pieces(cd)}
        vals = [f(v_min + (v_max - v_min) * i / self.GRID) for f in (ca, cd) for i in range(self.GRID + 1)]
        self.tol = 1e-10 * (max(vals) - min(vals) + 1e-300)

    def _pieces(self, f):
        """Breakpoints of the monotone pieces of f on [v_min, v_max] (local extrema refined by ternary search)."""
        h = (self.v_max - self.v_min) / self.GRID
        xs = [self.v_min + i * h for i in range(self.GRID + 1)]
        ys = [f(x) for x in xs]
        cuts = [self.v_min]
        for i in range(1, self.GRID):
            if (ys[i] - ys[i - 1]) * (ys[i + 1] - ys[i]) < 0:
                lo, hi, sign = xs[i - 1], xs[i + 1], 1 if ys[i] > ys[i - 1] else -1
                for _ in range(60):
                    a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
                    if sign * f(a) < sign * f(b):
                        lo = a
                    else:
                        hi = b
                cuts.append(0.5 * (lo + hi))
        cuts.append(self.v_max)
        return cuts

    def _root_in(self, f, a, b, u):
        """The root of f(x) = u in [a, b] where f is monotone and u between f(a), f(b); else None."""
        fa, fb = f(a) - u, f(b) - u
        if abs(fa) <= self.tol:
            return a
        if abs(fb) <= self.tol:
            return b
        if fa * fb > 0:
            return None
        for _ in range(80):
            mid = 0.5 * (a + b)
            fm = f(mid) - u
            if fm == 0.0 or b - a < 1e-14 * (1.0 + abs(mid)):
                break
            if fa * fm < 0:
                b = mid
            else:
                a, fa = mid, fm
        return 0.5 * (a + b)

    def max_root_below(self, which, u, x_hi):
        """max {x in [v_min, x_hi] : C(x) = u}, or None (C = C_d for 'd', C_a for 'a')."""
        f = self.cd if which == "d" else self.ca
        if abs(f(x_hi) - u) <= self.tol:
            return x_hi
        cuts = self.pieces[which]
        for i in range(len(cuts) - 2, -1, -1):
            a, b = cuts[i], min(cuts[i + 1], x_hi)
            if a > x_hi:
                continue
            r = self._root_in(f, a, b, u)
            if r is not None:
                return r
        return None

    def min_root_above(self, which, u, x_lo):
        """min {x in [x_lo, v_max] : C(x) = u}, or None."""
        f = self.cd if which == "d" else self.ca
        if abs(f(x_lo) - u) <= self.tol:
            return x_lo
        cuts = self.pieces[which]
        for i in range(len(cuts) - 1):
            a, b = max(cuts[i], x_lo), cuts[i + 1]
            if b < x_lo:
                continue
            r = self._root_in(f, a, b, u)
            if r is not None:
                return r
        return None


class Switch:
    """(2.3): C_a(v) when v rises, C_d(v) when it falls, u(t-1) when it stays."""

    def __init__(self, borders, v0, u0):
        self.b, self.v, self.u = borders, v0, u0

    def step(self, v):
        if v > self.v:
            self.u = self.b.ca(v)
        elif v < self.v:
            self.u = self.b.cd(v)
        self.v = v
        return self.u


class Backlash:
    """(2.4): C_d(v) if v <= max([v_m, v(t-1)] & C_d^-1(u(t-1))), else C_a(v) if
    v >= min([v(t-1), v_M] & C_a^-1(u(t-1))), else u(t-1) (horizontal move)."""

    def __init__(self, borders, v0, u0):
        self.b, self.v, self.u = borders, v0, u0
        self.cache = {}

    def step(self, v):
        if v != self.v:
            key = (self.v, self.u)
            if key not in self.cache:  # the pulse experiments revisit a few states over and over
                rd = self.b.max_root_below("d", self.u, self.v)
                ra = self.b.min_root_above("a", self.u, self.v)
                self.cache[key] = (rd, ra)
            rd, ra = self.cache[key]
            if rd is not None and v <= rd:
                self.u = self.b.cd(v)
            elif ra is not None and v >= ra:
                self.u = self.b.ca(v)
            if len(self.cache) > 20000:
                self.cache.clear()
        self.v = v
        return self.u


def make_operator(kind, borders, v0, u0):
    return (Switch if kind == "switch" else Backlash)(borders, v0, u0)


# ---------------------------------------------------------------- linear part


def poly_from_roots(roots):
    """Coefficients [1, a_1, ..., a_n] of prod (1 - r q^-1), real for conjugate pairs."""
    c = [1 + 0j]
    for r in roots:
        c = [c[i] - (r * c[i - 1] if i > 0 else 0) for i in range(len(c))] + [-r * c[-1]]
    return [x.real for x in c]


def roots_of(coeffs):
    """Roots z of z^n + c_1 z^(n-1) + ... + c_n (Durand-Kerner); coeffs = [1, c_1, ..., c_n]."""
    n = len(coeffs) - 1
    if n == 0:
        return []
    z = [(0.4 + 0.9j) ** k for k in range(n)]
    for _ in range(500):
        new = []
        for i in range(n):
            num = sum(c * z[i] ** (n - k) for k, c in enumerate(coeffs))
            den = 1
            for j in range(n):
                if j != i:
                    den *= z[i] - z[j]
            new.append(z[i] - num / den)
        z = new
    return z


def draw_linear(rng, n):
    """Stable A (poles in |z| <= 0.85) and B with positive DC gain, coprime with A."""
    while True:
        poles = []
        while len(poles) < n:
            if n - len(poles) >= 2 and rng.random() < 0.5:
                r, th = rng.uniform(0.4, 0.85), rng.uniform(0.15, 1.2)
                poles += [cmath.rect(r, th), cmath.rect(r, -th)]
            else:
                poles.append(rng.uniform(0.05, 0.85) if rng.random() < 0.9 else rng.uniform(-0.4, -0.05))
        a = poly_from_roots(poles)[1:]
        b = [rng.uniform(0.3, 1.0)] + [rng.uniform(-0.5, 1.0) for _ in range(n - 1)]
        if sum(b) < 0.3 * sum(abs(x) for x in b):
            continue
        zeros = roots_of([1.0] + [x / b[0] for x in b[1:]])
        if any(abs(z - p) < 0.15 for z in zeros for p in poles):
            continue  # A and B (nearly) share a root: not coprime
        gain = rng.uniform(0.5, 3.0)
        scale = gain * (1 + sum(a)) / sum(b)
        return a, [x * scale for x in b], [[p.real, p.imag] for p in poles]


def filter_ab(b, a, x):
    """y = B(q^-1)/A(q^-1) x with b = [b_1..b_n], a = [a_1..a_n], from rest (past x and y zero)."""
    n = len(a)
    y = [0.0] * len(x)
    for t in range(len(x)):
        s = 0.0
        for i in range(1, n + 1):
            if t - i < 0:
                break
            s += b[i - 1] * x[t - i] - a[i - 1] * y[t - i]
        y[t] = s
    return y


def impulse_energy(num, den, length=3000):
    """sum h(k)^2 of num(q^-1)/den(q^-1), num = [n_0..], den = [1, d_1..]."""
    h, energy = [], 0.0
    for t in range(length):
        s = num[t] if t < len(num) else 0.0
        for i in range(1, len(den)):
            if t - i >= 0:
                s -= den[i] * h[t - i]
        h.append(s)
        energy += s * s
    return energy


# ---------------------------------------------------------------- a random operator


def _cycle_ok(kind, borders, rng):
    """The cycle the DIS/AIS rely on (Fig. 7, Assumptions 1-2 in practice): from every state a random input
    reaches, v = v_M puts the point on (v_M, C_a(v_M)) and v = v_m on (v_m, C_d(v_m)); and for a backlash the
    descent from the top meets C_d over at least 40 % of the interval (not a Fig. 5 case)."""
    lo, hi = borders.v_min, borders.v_max
    u_top, u_bot = borders.ca(hi), borders.cd(lo)
    op = make_operator(kind, borders, lo, u_bot)
    v = lo
    for _ in range(600):
        v = rng.uniform(lo, hi) if rng.random() < 0.3 else min(hi, max(lo, v + rng.gauss(0, 0.05 * (hi - lo))))
        op.step(v)
        for target, want in ((hi, u_top), (lo, u_bot)):
            probe = make_operator(kind, borders, op.v, op.u)
            if abs(probe.step(target) - want) > 1e-9 * (1 + abs(want)):
                return False
    if kind == "backlash":
        op = make_operator(kind, borders, hi, u_top)
        on_cd = 0
        for i in range(1, 201):
            x = hi - (hi - lo) * i / 200
            if abs(op.step(x) - borders.cd(x)) < 1e-9 * (1 + abs(x)):
                on_cd += 1
        if on_cd < 80:
            return False
    return True


def draw_borders(rng, kind, v_min, v_max):
    """Curved C_a, C_d for a switch or backlash on [v_min, v_max]; returns (Borders, description)."""
    width = v_max - v_min
    while True:
        amp, off = rng.uniform(1.0, 4.0), rng.uniform(-2.0, 2.0)
        x_of = lambda v: (v - v_min) / width
        if kind == "switch":
            if rng.random() < 0.7:
                g, pg = draw_family(rng, rng.uniform(0.0, 1.0))
                h0, h1, h2 = rng.uniform(0.05, 0.25), rng.uniform(-0.2, 0.2), rng.uniform(-0.1, 0.1)
                h = lambda x: h0 + h1 * (x - 0.5) + h2 * x * x
                ca = lambda v, g=g, h=h: off + amp * (g(x_of(v)) + h(x_of(v)))
                cd = lambda v, g=g, h=h: off + amp * (g(x_of(v)) - h(x_of(v)))
                desc = {"mode": "band: C = off + amp (g(x) +- h(x)), h = h0 + h1 (x - 0.5) + h2 x^2",
                        "g": pg, "h0": h0, "h1": h1, "h2": h2}
            else:
                ga, pa = draw_family(rng, rng.uniform(0.0, 1.0))
                gd, pd = draw_family(rng, rng.uniform(0.0, 1.0))
                dlt = rng.uniform(0.0, 0.15)
                ca = lambda v, ga=ga: off + amp * (ga(x_of(v)) + dlt)
                cd = lambda v, gd=gd: off + amp * (gd(x_of(v)) - dlt)
                desc = {"mode": "two curves: C_a = off + amp (g_a(x) + delta), C_d = off + amp (g_d(x) - delta)",
                        "g_a": pa, "g_d": pd, "delta": dlt}
        else:
            g, pg = draw_family(rng, rng.uniform(0.5, 1.0))
            gap = rng.uniform(0.05, 0.25) * width
            bump = (rng.uniform(0, 1), rng.gauss(0, 0.08), rng.uniform(0.1, 0.3)) if rng.random() < 0.3 else None
            eps = (lambda x: bump[1] * math.exp(-0.5 * ((x - bump[0]) / bump[2]) ** 2)) if bump else (lambda x: 0.0)
            ca = lambda v, g=g: off + amp * g(x_of(v - gap / 2))
            cd = lambda v, g=g, e=eps: off + amp * (g(x_of(v + gap / 2)) + e(x_of(v)))
            desc = {"mode": "shifted: C_a(v) = G(v - gap/2), C_d(v) = G(v + gap/2) + off-shape bump",
                    "g": pg, "gap": gap, "cd_bump_center_height_width": bump}
        desc.update({"offset": off, "amplitude": amp, "x": "(v - v_min) / (v_max - v_min)"})
        borders = Borders(ca, cd, v_min, v_max)
        if abs(ca(v_max) - cd(v_min)) < 0.25 * amp:
            continue  # Assumption 2 (2.5), with a margin
        if _cycle_ok(kind, borders, rng):
            return borders, desc
