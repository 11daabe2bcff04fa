"""What the viewer draws, from a spec's geometry and a trajectory alone (no mesh files).

Everything is placed in the fixed frame ê⁰ of the digest, where ê⁰₁ points down along gravity,
by the independent numeric kinematics of ``reference`` (direction cosines (14)/(15) and the
platform's attitude R(t), position r₀(t)).  For every frame time:

    joint axis lᵏ       a bar along eᵏ through Oᵏ, in body k's colour
    link k             the segment Oᵏ → Oᵏ⁺¹ (the last body: Oⁿ → its tip, below)
    centre of mass Gᵏ  Gᵏ = Oᵏ + cᵏ, a dot of volume ∝ mᵏ; a thin line Oᵏ → Gᵏ where Gᵏ is off the link
    rotor              where λᵏ ≠ 0: a disc normal to λᵏ centred at Gᵏ, its axle, and a spoke turning
                       about λᵏ in the sense of λᵏ (at a nominal rate: the spec gives the rotor's
                       momentum, not its inertia, so the true spin rate is not known)
    platform           where the spec has a base: a square translucent deck through O¹ across the
                       platform's ê⁰₁, larger than the chain, with the platform's triad
    fixed frame        the triad ê⁰₁ ê⁰₂ ê⁰₃ at the origin (labelled 1 2 3); gravity is drawn by the
                       renderers as an arrow "g" along ê⁰₁ in a corner
    trace              the last body's tip over the last ``trace`` seconds, fading

The tip of the last body is Gⁿ when cⁿ ≠ 0, else the end of its rotor's axle, else the end of
its ê ⁿ₃ bar.  A primitive is a tuple in fixed-frame coordinates:

    ("seg", p, q, colour, width)        width in pixels of a 480-pixel-high picture
    ("dot", p, radius, colour)          radius in metres
    ("disc", c, u, v, radius, colour)   the circle c + radius (u cos a + v sin a), u ⟂ v unit vectors
    ("ring", c, u, v, radius, colour)   the same circle, not filled (a Cardan ring)
    ("plate", c, u, v, half, colour)    the square c ± half u ± half v, translucent (the platform)
    ("label", p, text, colour, o)       text at p, the end of an axis from o (a renderer moves it outwards from o
                                        where it would cover another label)

Both renderers (the raster one in ``animate`` and the browser's in templates/viewer.js) draw the
same primitives: they only project them with ``Camera`` (orthographic, orbiting about the vertical
−ê⁰₁), sort them far to near and paint.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..derive import reference

# body colours of a short chain (colour-blind-safe, after Okabe & Ito; their yellow, faint on white,
# and black, the colour of the legend's symbols, replaced by Tol's wine and olive); a longer chain is
# coloured by its index along a colour map (viridis up to 0.8: no yellow), which the legend names
BODY_COLOURS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#882255", "#999933"]
COLOUR_MAP = ("viridis", ["#440154", "#414487", "#2A788E", "#22A884", "#7AD151"])
FRAME_COLOUR = "#888888"
PLATFORM_COLOUR = "#8C7B6B"
TRACE_COLOUR = "#C0392B"
SPOKE_RATE = 2 * math.pi * 0.75  # rad/s of the rotor's spoke (nominal, see above)


def body_colour(k: int) -> str:
    """Body k's colour (k from 1) in a chain of at most len(BODY_COLOURS) bodies."""
    return BODY_COLOURS[(k - 1) % len(BODY_COLOURS)]


def body_colours(n: int) -> list[str]:
    """The colours of the n bodies: BODY_COLOURS for a short chain, else the colour map by index."""
    if n <= len(BODY_COLOURS):
        return BODY_COLOURS[:n]
    anchors = np.array([[int(c[i:i + 2], 16) for i in (1, 3, 5)] for c in COLOUR_MAP[1]], float)
    x = np.linspace(0.0, len(anchors) - 1.0, n)
    lo = np.minimum(np.floor(x).astype(int), len(anchors) - 2)
    rgb = anchors[lo] + (x - lo)[:, None] * (anchors[lo + 1] - anchors[lo])
    return ["#%02X%02X%02X" % tuple(int(round(v)) for v in c) for c in rgb]


# --------------------------------------------------------------------------- the camera
class Camera:
    """Orthographic view of the fixed frame ê⁰ with −ê⁰₁ up.  The world is first written in the
    right-handed frame (X, Y, Z) = (x₃, x₂, −x₁) (Z up); the camera sits at azimuth ``az`` about Z
    (from X towards Y) and elevation ``el`` above the horizontal plane (radians).  ``project``
    gives the screen's right and up coordinates (metres) and the depth (larger: nearer)."""

    def __init__(self, az: float, el: float):
        self.az, self.el = az, el
        ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)
        d = np.array([ce * ca, ce * sa, se])  # towards the camera
        r = np.array([-sa, ca, 0.0])
        u = np.cross(d, r)
        W = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # rows: X, Y, Z in ê⁰
        self.matrix = np.vstack([r, u, d]) @ W  # rows: right, up, towards the camera, in ê⁰

    def project(self, p) -> np.ndarray:
        """(..., 3) fixed-frame points → (..., 3) right, up, depth."""
        return np.asarray(p, dtype=float) @ self.matrix.T


def default_camera(points: np.ndarray) -> Camera:
    """A view across the plane the motion spreads in most: the azimuth of least horizontal spread
    of the points, turned 30° so that the third dimension shows, from 25° above."""
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    H = np.stack([P[:, 2], P[:, 1]], axis=1)  # X = x₃, Y = x₂
    H = H - H.mean(axis=0)
    C = H.T @ H
    if np.allclose(C, 0.0):
        az = math.radians(30.0)
    else:
        w, V = np.linalg.eigh(C)
        least = V[:, 0]
        az = math.atan2(least[1], least[0])
        az = (az + math.pi / 2) % math.pi - math.pi / 2 + math.radians(30.0)  # one of ± least: the one near 0
    return Camera(az, math.radians(25.0))


# --------------------------------------------------------------------------- the scene
@dataclass
class Scene:
    name: str
    times: np.ndarray  # (F,)
    frames: list  # per frame: the list of primitives that move
    static: list  # primitives drawn in every frame
    tip_times: np.ndarray  # (T,) the times of the tip's trace (finer than the frames where known)
    tips: np.ndarray  # (T, 3) the last body's tip there
    trace: float  # seconds of trace shown
    size: float  # the chain's characteristic length (m)
    gravity: bool
    integral: dict | None = None  # {"label", "values"}: the plot under the HTML scene
    points: np.ndarray = field(default=None)  # every key point of every frame (for fitting the view)
    states: np.ndarray | None = None  # (F, 2n) φ, φ̇ at the frames (the page's readout), None if φ̇ is unknown
    legend: list = field(default_factory=list)  # [(symbol, text)]: what the picture's marks are (legend())
    caption: str = ""  # a line the picture carries about how it was drawn (a fast platform drawn about its mean)
    colours: list = field(default_factory=list)  # the bodies' colours, body 1 first


def _unit(v):
    nv = np.linalg.norm(v)
    return v / nv if nv > 0 else v


def _perp(n):
    """A unit vector perpendicular to the unit vector n (deterministic)."""
    a = np.eye(3)[int(np.argmin(np.abs(n)))]
    return _unit(a - n * (a @ n))


class Geometry:
    """The spec's fixed sizes: radii of gyration, bar half-lengths, dot and disc radii."""

    def __init__(self, ch: reference.NumericChain):
        n = ch.n
        self.ch = ch
        rg = []
        for k in range(n):
            c, m = ch.c[k], ch.m[k]
            AG = ch.A[k] - m * ((c @ c) * np.eye(3) - np.outer(c, c))  # about Gᵏ
            rg.append(math.sqrt(max(np.trace(AG), 0.0) / (2 * m)) if m > 0 else 0.0)
        self.rg = np.array(rg)
        reach = float(sum(np.linalg.norm(ch.s[k]) for k in range(n - 1)) + np.linalg.norm(ch.c[-1]))
        self.size = max(reach, float(self.rg.max()), 1e-3)
        self.ring = np.array([_ring_radius(ch, k) for k in range(n)])  # 0: not drawn as a Cardan ring
        # the marks of a body scale with the whole picture, but not beyond six times its own
        # link (a cable of many short links stays a cable)
        own = np.array([max(np.linalg.norm(ch.s[k] if k < n - 1 else ch.c[k]), self.rg[k]) for k in range(n)])
        scale = np.minimum(self.size, 6.0 * own)
        scale = np.where(scale > 0, scale, self.size)
        self.bar = np.maximum(0.8 * self.rg, 0.15 * scale)
        # an axis reaches the ring whose bearings hold it (the one before) and its own ring
        self.bar = np.maximum(self.bar, 1.12 * np.maximum(self.ring, np.concatenate([[0.0], self.ring[:-1]])))
        mmax = float(ch.m.max()) if ch.m.max() > 0 else 1.0
        self.dot = np.maximum(0.05 * scale * np.cbrt(np.maximum(ch.m, 0) / mmax), 0.02 * scale)
        self.disc = np.maximum(0.7 * self.rg, 0.12 * scale)
        self.colours = body_colours(n)
        # the platform's deck: beyond every ring and rotor drawn about O¹, so that nothing merges with it
        self.deck = 1.15 * max(0.6 * self.size, float(np.max(self.ring, initial=0.0)), float(np.max(self.disc)))


def pose(ch: reference.NumericChain, phi, t: float) -> dict:
    """Fixed-frame kinematics at (φ, t): body frames R (rows êᵏᵢ), O, e, G, λ (body→fixed), the
    platform's attitude R0 and position r0."""
    R0, _w, _e, r0, _v, _a = reference.platform(ch, t)
    R = reference.frames(ch, phi) @ R0.T
    e, c, s, lam, A, O = reference.world(ch, phi, t)
    return dict(R=R, O=O, e=e, G=O + c, lam=lam, s=s, R0=R0, r0=r0)


def frame_primitives(geo: Geometry, P: dict, t: float, base: bool) -> tuple[list, list]:
    """The moving primitives of one frame and its key points."""
    ch, n = geo.ch, geo.ch.n
    prims, keys = [], []
    if base:
        R0, r0 = P["R0"], P["r0"]
        ey, ez = R0[:, 1], R0[:, 2]  # the platform's axes 2, 3 in ê⁰
        a = geo.deck
        prims.append(("plate", r0, ey, ez, a, PLATFORM_COLOUR))  # the deck, across the platform's ê⁰₁
        turns = ch.general is not None and bool(ch.general.rotations)
        for j, lab in enumerate("123" if turns else ""):  # a deck that only translates keeps the fixed axes' directions
            q = r0 + 0.5 * a * R0[:, j]
            prims.append(("seg", r0, q, PLATFORM_COLOUR, 1.2))
            prims.append(("label", q, lab, PLATFORM_COLOUR, r0))
        keys += [r0 + a * (i * ey + j * ez) for i in (-1, 1) for j in (-1, 1)]
    for k in range(n):
        col = geo.colours[k]
        O, e, G = P["O"][k], P["e"][k], P["G"][k]
        b = geo.bar[k]
        prims.append(("seg", O - b * e, O + b * e, col, 5.0))
        keys += [O - b * e, O + b * e]
        ring = cardan_ring(geo, P, k)
        if ring is not None:
            u, v, r = ring
            prims.append(("ring", O, u, v, r, col))
            keys += _around(O, u, v, r)
        lam = P["lam"][k]
        rotor = np.linalg.norm(lam) > 0
        end, link = link_end(geo, P, k)
        if link and np.linalg.norm(end - O) > 0:
            prims.append(("seg", O, end, col, 3.5))
        elif not link and not rotor:  # the last body's bar along êⁿ₃
            prims.append(("seg", O, end, col, 1.5))
        # G off the link: a thin line to it
        d = end - O
        L2 = d @ d
        off = G - O - (((G - O) @ d) / L2 * d if L2 > 0 else 0.0)
        if np.linalg.norm(off) > 0.02 * geo.size:
            prims.append(("seg", O, G, col, 1.0))
        prims.append(("dot", G, geo.dot[k], col))
        keys += [O, G, end]
        if rotor:
            nrm = _unit(lam)
            # a body-fixed direction across λ, turned about λ by the spoke's angle
            u0 = _perp(ch.lam[k] / np.linalg.norm(ch.lam[k])) if np.linalg.norm(ch.lam[k]) > 0 else _perp(nrm)
            u0 = P["R"][k].T @ u0  # body → fixed
            u0 = _unit(u0 - nrm * (u0 @ nrm))
            w0 = np.cross(nrm, u0)
            ang = SPOKE_RATE * t
            u = math.cos(ang) * u0 + math.sin(ang) * w0
            v = np.cross(nrm, u)
            r = geo.disc[k]
            prims.append(("disc", G, u, v, r, col))
            prims.append(("seg", G, G + r * u, "#FFFFFF", 2.0))
            prims.append(("seg", G - 1.3 * r * nrm, G + 1.3 * r * nrm, col, 1.5))
            keys += _around(G, u, v, r) + [G + 1.3 * r * nrm, G - 1.3 * r * nrm]
    return prims, keys


def _around(c, u, v, r, count: int = 16) -> list:
    """Points on the circle c + r (u cos a + v sin a): whatever the view, the picture of the circle
    lies within a few per cent of theirs (the view is fitted to key points)."""
    a = np.linspace(0.0, 2 * math.pi, count, endpoint=False)
    return list(np.asarray(c) + r * (np.cos(a)[:, None] * np.asarray(u) + np.sin(a)[:, None] * np.asarray(v)))


def _ring_radius(ch: reference.NumericChain, k: int) -> float:
    """A ring of a Cardan suspension — a body that carries the next axis (or, the last, its rotor's
    axle) across its own through the same point (s = 0 but for the last) — is drawn as a ring
    through the bearings it carries, in the plane of its axis eᵏ and the next axis, of the radius
    of a thin ring with its inertia about eᵏ: r = √(2 eᵏ·Aᵏ·eᵏ / mᵏ), whatever its centre of mass
    as long as that lies inside the ring (|cᵏ| < r/2; a heavier offset is a pendulum, drawn as a
    link).  0 where none."""
    n = ch.n
    if (k < n - 1 and np.linalg.norm(ch.s[k]) > 0) or ch.m[k] <= 0:
        return 0.0
    # the next axis in body k's frame is ê^k_1 turned by θ^{k+1} about ê^k_2; the rotor's axle is λᵏ
    across = abs(math.sin(ch.theta[k + 1])) if k < n - 1 else float(np.hypot(ch.lam[k][1], ch.lam[k][2]))
    inertia = float(ch.A[k][0, 0])  # about ê^k_1 = eᵏ
    r = math.sqrt(2.0 * inertia / ch.m[k]) if across > 1e-9 and inertia > 0 else 0.0
    return r if np.linalg.norm(ch.c[k]) < 0.5 * r else 0.0


def cardan_ring(geo: Geometry, P: dict, k: int):
    """Body k's Cardan ring at the pose P: (u, v, r) with u = eᵏ and v across it in the ring's
    plane, or None (see _ring_radius)."""
    r = geo.ring[k]
    if r <= 0:
        return None
    u = P["e"][k]
    w = np.asarray(P["e"][k + 1] if k < geo.ch.n - 1 else P["lam"][k], float)
    v = w - (w @ u) * u
    return (u, _unit(v), r) if np.linalg.norm(v) > 0 else None


def link_end(geo: Geometry, P: dict, k: int) -> tuple[np.ndarray, bool]:
    """Where body k's drawing ends (the last body's: its tip) and whether that is a link:
    Oᵏ⁺¹; for the last body Gⁿ (a link to it) where cⁿ ≠ 0, else the end of its rotor's axle,
    else the end of a bar along êⁿ₃."""
    n = geo.ch.n
    if k < n - 1:
        return P["O"][k + 1], True
    if np.linalg.norm(geo.ch.c[k]) > 0:
        return P["G"][k], True
    if np.linalg.norm(P["lam"][k]) > 0:
        return P["G"][k] + geo.disc[k] * 1.3 * _unit(P["lam"][k]), False
    return P["O"][k] + geo.bar[k] * P["R"][k][2], False


def static_primitives(geo: Geometry) -> list:
    a = 0.3 * geo.size
    out = []
    for j, lab in enumerate("123"):
        q = np.eye(3)[j] * a
        out.append(("seg", np.zeros(3), q, FRAME_COLOUR, 1.2))
        out.append(("label", q * 1.12, lab, FRAME_COLOUR, np.zeros(3)))
    return out


_POINTS = {"seg": (1, 2), "dot": (1,), "disc": (1,), "ring": (1,), "plate": (1,), "label": (1, 4)}  # the arguments that are points


def shifted(prim: tuple, d: np.ndarray) -> tuple:
    """The primitive moved by d (its points; a disc's directions stay)."""
    return tuple(a + d if i in _POINTS[prim[0]] else a for i, a in enumerate(prim))


def legend(frames: list, static: list, trace: float, n: int) -> list[tuple[str, str]]:
    """The legend of a scene, read off the primitives it draws: one entry per kind of mark in
    any frame (symbols: bar, link, dot, disc, deck, triad, trace), after the bodies' colours
    ("bodies": each number in its colour; "bodymap": the colours of a long chain, as a strip)."""
    marks = set()
    for prim in static + [p for f in frames for p in f]:
        if prim[0] == "seg" and prim[4] == 5.0:
            marks.add("bar")
        elif prim[0] == "seg" and prim[4] == 3.5:
            marks.add("link")
        elif prim[0] == "ring":
            marks.add("ring")
        elif prim[0] == "plate":
            marks.add("deck" if any(p[0] == "label" and p[3] == PLATFORM_COLOUR for f in frames[:1] for p in f)
                      else "deck_only")
        elif prim[0] in ("dot", "disc"):
            marks.add(prim[0])
        elif prim[0] == "label" and prim[3] == FRAME_COLOUR:
            marks.add("triad")
    if trace > 0:
        marks.add("trace")
    words = {"bar": "joint axis", "link": "link", "ring": "Cardan ring",
             "dot": "centre of mass (size: mass)",
             "disc": "rotor (white spoke: its sense)", "deck": "platform, its axes 1 2 3", "deck_only": "platform (it only translates)",
             "triad": "fixed axes 1 2 3 (1 down)", "trace": f"path of the tip, last {trace:g} s"}
    bodies = (("bodies", "body " + " ".join(str(k) for k in range(1, n + 1))) if n <= len(BODY_COLOURS)
              else ("bodymap", f"bodies 1…{n}, from the first colour to the last"))
    return [bodies] + [(k, words[k]) for k in words if k in marks]


def build(spec, ch: reference.NumericChain, times, X, trace: float = 2.0, integral: dict | None = None,
          tip_times=None, tip_X=None, rates: bool = True, follow: bool = False) -> Scene:
    """The scene of the trajectory X (states at the frame ``times``); the trace follows
    (tip_times, tip_X), a finer sampling of the same motion, where given.  ``rates``: X holds
    true φ̇ (the page shows them).  ``follow``: everything is drawn relative to the platform's
    O¹ = r₀(t), so that a heaving platform stays in the middle of the view."""
    geo = Geometry(ch)
    base = spec.base is not None
    n = ch.n
    static = static_primitives(geo)

    def offset(t):
        return -np.asarray(reference.platform(ch, float(t))[3], float) if follow else np.zeros(3)

    frames, keys = [], [np.zeros(3)]
    for t, x in zip(times, X):
        prims, k = frame_primitives(geo, pose(ch, np.asarray(x[:n], float), float(t)), float(t), base)
        d = offset(t)
        if follow:
            prims = [shifted(p, d) for p in static + prims]
        frames.append(prims)
        keys += [p + d for p in k] + [q + d for p in static if p[0] == "seg" for q in (p[1], p[2])]
    if tip_times is None:
        tip_times, tip_X = times, X
    tips = np.array([link_end(geo, pose(ch, np.asarray(x[:n], float), float(t)), n - 1)[0] + offset(t)
                     for t, x in zip(tip_times, tip_X)])
    tip_times = np.asarray(tip_times, float)
    shown = (tip_times >= float(times[0]) - trace - 1e-12) & (tip_times <= float(times[-1]) + 1e-12)
    if trace > 0:
        keys += list(tips[shown])  # the picture is framed to the path it draws, too
    return Scene(name=spec.name, times=np.asarray(times, float), frames=frames, static=[] if follow else static,
                 tip_times=np.asarray(tip_times, float), tips=tips, trace=trace, size=geo.size, gravity=ch.g != 0,
                 integral=integral, points=np.array(keys), states=np.asarray(X, float)[:, :2 * n] if rates else None,
                 legend=legend(frames, [] if follow else static, trace, n), colours=geo.colours)
