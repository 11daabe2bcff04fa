"""The raster picture of a scene: ``Raster`` paints its primitives with Pillow, 2× supersampled,
in depth order (a thick bar in pieces ordered against the discs it crosses), with the name, the
clock, the direction of gravity, a caption and the legend.  ``animate`` encodes its frames as GIF,
MP4 or PNG."""
from __future__ import annotations

import math

import numpy as np

from .scene import FRAME_COLOUR, PLATFORM_COLOUR, TRACE_COLOUR, Camera, Scene, default_camera
from ..chainspec.spec import SpecError


def _rgb(hexcol: str) -> tuple:
    return tuple(int(hexcol[i:i + 2], 16) for i in (1, 3, 5))


def occluders(prims: list, cam) -> list:
    """The discs of a frame as the planes a bar is ordered against: (centre, unit normal, radius,
    depth of the centre)."""
    out = []
    for prim in prims:
        if prim[0] == "disc":
            c = np.asarray(prim[1], float)
            out.append((c, np.cross(prim[2], prim[3]), float(prim[4]), float(cam.project(c)[2])))
    return out


def seg_pieces(prim: tuple, discs: list, cam, pieces: int = 8) -> list:
    """A thick segment in pieces, each with the depth it is painted at: its own, except where it
    lies over a disc on the screen, where it goes just in front of the disc if it is on the
    camera's side of the disc's plane and just behind otherwise (a bar through a rotor shows
    through on the far side and over it on the near side, whatever their mean depths)."""
    _, p, q, col, w = prim
    p, q = np.asarray(p, float), np.asarray(q, float)
    view = cam.matrix[2]  # towards the camera
    out = []
    for j in range(pieces):
        a, b = p + (q - p) * j / pieces, p + (q - p) * (j + 1) / pieces
        m = (a + b) / 2
        depth = float(cam.project(m)[2])
        for c, nrm, r, dc in discs:
            dn = float(view @ nrm)
            if abs(dn) < 1e-9:
                continue
            hit = m - ((m - c) @ nrm) / dn * view  # where the line of sight through m meets the plane
            if np.linalg.norm(hit - c) <= r:
                eps = 1e-9 * max(1.0, r)
                depth = max(depth, dc + eps) if (m - hit) @ view > 0 else min(depth, dc - eps)
        out.append((("seg", a, b, col, w), depth))
    return out


def _inside(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Which of the points lie inside the polygon (even–odd rule)."""
    x, y = pts[:, 0][:, None], pts[:, 1][:, None]
    x0, y0 = poly[:, 0][None, :], poly[:, 1][None, :]
    x1, y1 = np.roll(poly[:, 0], -1)[None, :], np.roll(poly[:, 1], -1)[None, :]
    crosses = ((y0 > y) != (y1 > y)) & (x < x0 + (y - y0) * (x1 - x0) / np.where(y1 != y0, y1 - y0, 1e-300))
    return crosses.sum(axis=1) % 2 == 1


class Raster:
    """Paints a scene's frames with Pillow, at ``ss``× the size and then reduced (anti-aliasing)."""

    BACKGROUND = (255, 255, 255)

    def __init__(self, scene: Scene, width: int = 480, height: int = 480, camera: Camera | None = None, ss: int = 2):
        try:
            from PIL import Image, ImageDraw, ImageFont
        except ImportError:
            raise SpecError("-o", "pictures need Pillow: pip install 'gyrochain[view]' (or write .html)") from None
        self.Image, self.ImageDraw = Image, ImageDraw
        self.scene, self.W, self.H, self.ss = scene, width, height, ss
        self.cam = camera or default_camera(scene.points)
        k = height / 480.0 * ss
        self.k = k
        # text no smaller than 12 and 11 pixels in the final picture, however small it is
        self.font = ImageFont.load_default(size=round(max(12.0, 14 * height / 480.0) * ss))
        self.small = ImageFont.load_default(size=round(max(11.0, 12 * height / 480.0) * ss))
        self.line = max(15 * k, 1.3 * self.small.size)  # a legend row, supersampled pixels
        # the clock: enough decimals to change from one frame to the next
        steps = np.diff(scene.times)
        step = float(np.min(steps[steps > 0])) if np.any(steps > 0) else 1.0
        self.decimals = max(2, math.ceil(-math.log10(step) - 1e-9))
        # fit every key point of every frame, below the two text lines and above the legend
        self.rows = self._legend_rows()
        if len(self.rows) * self.line > 0.3 * height * ss:  # too small a picture for a legible legend: none
            self.rows = []
        self.band = (len(self.rows) * self.line + 6 * k) / ss if self.rows else 0.0  # in final pixels
        P = self.cam.project(scene.points)[:, :2]
        lo, hi = P.min(axis=0), P.max(axis=0)
        span = np.maximum(hi - lo, 1e-9)
        top = (8 * k + self.font.size * 2.4) / ss
        margin = 0.06 * min(width, height)
        room = height - top - self.band
        self.scale = min((width - 2 * margin) / span[0], (room - 2 * margin) / span[1]) * ss
        self.centre = (lo + hi) / 2
        self.origin = np.array([width / 2 * ss, (top + room / 2) * ss])
        self.top = top
        self.boxes: list = []  # (kind, x0, y0, x1, y1) in final pixels of everything the last frame drew

    def _px(self, p):
        """Fixed-frame points → x (right), y (down) on the supersampled canvas, and depth."""
        q = self.cam.project(p)
        xy = (q[..., :2] - self.centre) * self.scale
        return self.origin[0] + xy[..., 0], self.origin[1] - xy[..., 1], q[..., 2]

    def to_pixels(self, p) -> np.ndarray:
        """Fixed-frame points → pixel coordinates of the final picture (x right, y down) and depth."""
        x, y, z = self._px(p)
        return np.stack([x / self.ss, y / self.ss, z], axis=-1)

    def frame(self, i: int):
        """Frame i as an RGB image."""
        sc, k = self.scene, self.k
        img = self.Image.new("RGB", (self.W * self.ss, self.H * self.ss), self.BACKGROUND)
        draw = self.ImageDraw.Draw(img, "RGBA")
        items = []  # (depth, order, painter)
        t = sc.times[i]
        # the trace of the tip over the last sc.trace seconds, fading
        j0 = int(np.searchsorted(sc.tip_times, t - sc.trace - 1e-12))
        j1 = int(np.searchsorted(sc.tip_times, t + 1e-12, side="right"))
        tr = sc.tips[j0:j1]
        if len(tr) > 1:
            x, y, z = self._px(tr)
            col = _rgb(TRACE_COLOUR)
            for j in range(len(tr) - 1):
                a = int(255 * 0.85 * (j + 1) / (len(tr) - 1))
                seg = (x[j], y[j], x[j + 1], y[j + 1])
                items.append((min(z[j], z[j + 1]), len(items),
                              lambda seg=seg, a=a: draw.line(seg, fill=col + (a,), width=max(1, round(1.8 * k)))))
        prims = sc.static + sc.frames[i]
        discs = occluders(prims, self.cam)
        self.boxes = [("path", *self._bbox(tr))] if len(tr) else []
        labels = [p for p in prims if p[0] == "label"]
        for prim in prims:
            if prim[0] == "label":
                continue
            self.boxes.append((prim[0], *self._bbox(self._outline(prim))))
            if prim[0] == "seg" and prim[4] >= 2.0 and discs:  # in pieces, each ordered against the discs
                items += [self._item(draw, piece, len(items), depth) for piece, depth in seg_pieces(prim, discs, self.cam)]
            else:
                items.append(self._item(draw, prim, len(items)))
        items += self._labels(draw, labels, [p for p in prims if p[0] == "disc"], len(items))
        for _, _, paint in sorted(items, key=lambda it: (it[0], it[1])):
            paint()
        self._overlay(draw, t)
        return img.reduce(self.ss)  # the mean of each ss × ss block: anti-aliasing

    def _item(self, draw, prim, order, depth=None):
        kind, k = prim[0], self.k
        if kind == "seg":
            _, p, q, col, w = prim
            x, y, z = self._px(np.array([p, q]))
            return (z.mean() if depth is None else depth, order,
                    lambda: draw.line((x[0], y[0], x[1], y[1]), fill=_rgb(col), width=max(1, round(w * k))))
        if kind == "dot":
            _, p, r, col = prim
            x, y, z = self._px(np.asarray(p))
            rp = max(r * self.scale, 2.5 * k)
            return (float(z), order, lambda: draw.ellipse((x - rp, y - rp, x + rp, y + rp), fill=_rgb(col),
                                                          outline=(40, 40, 40), width=max(1, round(k))))
        if kind == "disc":
            _, c, u, v, r, col = prim
            poly, z = self._circle(c, u, v, r, 48)
            return (z.mean(), order, lambda: draw.polygon(poly, fill=_rgb(col) + (76,), outline=_rgb(col), width=max(1, round(1.5 * k))))
        if kind == "ring":
            _, c, u, v, r, col = prim
            ring, z = self._circle(c, u, v, r, 64)
            return (z.mean(), order, lambda: draw.line(ring + ring[:1], fill=_rgb(col), width=max(1, round(2.5 * k)), joint="curve"))
        if kind == "plate":
            _, c, u, v, a, col = prim
            x, y, z = self._px(self._outline(prim))
            poly = list(zip(x.tolist(), y.tolist()))
            return (z.mean(), order, lambda: draw.polygon(poly, fill=_rgb(col) + (28,), outline=_rgb(col) + (150,),
                                                          width=max(1, round(k))))
        raise ValueError(kind)

    def _clear_spot(self, box, d, step, hard, discs, pad):
        """The box moved the least, outwards along d first, then turning (±45°, ±90°, …), until it
        covers no hard box and no disc and stays inside the scene's area; the box itself if none."""
        turns = [d]
        for k in (1, -1, 2, -2, 3, -3, 4):
            a = k * math.pi / 4
            turns.append(np.array([d[0] * math.cos(a) - d[1] * math.sin(a), d[0] * math.sin(a) + d[1] * math.cos(a)]))
        for j in range(60):
            for u in turns if j else turns[:1]:
                dx, dy = j * step * u
                cand = (box[0] + dx, box[1] + dy, box[2] + dx, box[3] + dy)
                if not (0 <= cand[0] and cand[2] <= self.W and self.top <= cand[1] and cand[3] <= self.H - self.band):
                    continue
                corners = np.array([(cand[0], cand[1]), (cand[2], cand[1]), (cand[2], cand[3]), (cand[0], cand[3]),
                                    ((cand[0] + cand[2]) / 2, (cand[1] + cand[3]) / 2)])
                if not any(cand[0] - pad < h[2] and h[0] < cand[2] + pad and cand[1] - pad < h[3] and h[1] < cand[3] + pad
                           for h in hard) and not any(_inside(poly, corners).any() for poly in discs):
                    return cand
        return box

    def _outline(self, prim) -> np.ndarray:
        """Fixed-frame points whose projection bounds what ``prim`` paints."""
        kind = prim[0]
        if kind == "seg":
            return np.array([prim[1], prim[2]], float)
        if kind == "dot":
            c, r = np.asarray(prim[1], float), max(prim[2], 2.5 * self.k / self.scale)
            return c + r * np.concatenate([np.eye(3), -np.eye(3)])
        c, u, v, r = (np.asarray(a, float) for a in prim[1:5])
        if kind == "plate":
            return np.array([c + r * (i * u + j * v) for i, j in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
        a = np.linspace(0.0, 2 * math.pi, 32, endpoint=False)
        return c + r * (np.cos(a)[:, None] * u + np.sin(a)[:, None] * v)

    def _bbox(self, pts) -> tuple:
        x, y, _ = self._px(np.asarray(pts, float))
        return (float(x.min()) / self.ss, float(y.min()) / self.ss, float(x.max()) / self.ss, float(y.max()) / self.ss)

    def _labels(self, draw, labels: list, discs: list, order: int) -> list:
        """The labels (the axes' 1 2 3) placed so that none covers another, a centre of mass, the
        text lines or the legend: each starts where its axis ends and steps outwards (away from
        the middle of its axes) until it is clear; their boxes join ``self.boxes``."""
        ss, pad = self.ss, 2.0
        hard = [b[1:] for b in self.boxes if b[0] == "dot"]
        hard += [(0, 0, self.W, self.top), (0, self.H - self.band, self.W, self.H)]
        discs = [np.array(self._px(self._outline(p))[:2]).T / ss for p in discs]
        items = []
        for prim in labels:
            _, p, text, col, o = prim
            x, y, z = self._px(np.asarray(p, float))
            x, y = float(x) / ss, float(y) / ss
            ox, oy, _ = self._px(np.asarray(o, float))
            d = np.array([x - float(ox) / ss, y - float(oy) / ss])
            d = d / np.linalg.norm(d) if np.linalg.norm(d) > 1e-6 else np.array([0.7071, -0.7071])
            l, t, r, b = (v / ss for v in draw.textbbox((0, 0), text, font=self.small, anchor="mm"))
            box = (x + l, y + t, x + r, y + b)
            box = self._clear_spot(box, d, 0.5 * (b - t), hard, discs, pad)
            hard.append(box)
            self.boxes.append(("label", *box))
            cx, cy = (box[0] + box[2]) / 2 * ss, (box[1] + box[3]) / 2 * ss
            items.append((float(z), order + len(items),
                          lambda cx=cx, cy=cy, text=text, col=col: draw.text((cx, cy), text, fill=_rgb(col), font=self.small, anchor="mm")))
        return items

    def _circle(self, c, u, v, r, count: int):
        """A circle of radius r about c in the plane of u, v: its pixels and their depths."""
        a = np.linspace(0.0, 2 * math.pi, count, endpoint=False)
        pts = np.asarray(c) + r * (np.cos(a)[:, None] * np.asarray(u) + np.sin(a)[:, None] * np.asarray(v))
        x, y, z = self._px(pts)
        return list(zip(x.tolist(), y.tolist())), z

    def _legend_rows(self) -> list:
        """The legend's entries laid out in rows across the picture: [[(symbol, text, x), …], …]."""
        k, rows, x = self.k, [[]], 8 * self.k
        for sym, text in self.scene.legend:
            w = {"bodies": 0.0, "bodymap": 46 * k}.get(sym, 40 * k) + 10 * k + self.small.getlength(text)
            if rows[-1] and x + w > self.W * self.ss - 8 * k:
                rows.append([])
                x = 8 * k
            rows[-1].append((sym, text, x))
            x += w
        return rows if rows[0] else []

    def _legend(self, draw):
        k, H = self.k, self.H * self.ss
        grey, y0 = (85, 85, 85), H - len(self.rows) * self.line - 3 * k
        colours = self.scene.colours
        for r, row in enumerate(self.rows):
            y = y0 + (r + 0.5) * self.line
            for sym, text, x in row:
                if sym == "bodies":  # "body 1 2 …", each number in its body's colour
                    words = text.split()
                    draw.text((x, y), words[0], fill=(60, 60, 60), font=self.small, anchor="lm")
                    x += self.small.getlength(words[0] + " ")
                    for j, word in enumerate(words[1:]):
                        draw.text((x, y), word, fill=_rgb(colours[j]), font=self.small, anchor="lm")
                        x += self.small.getlength(word + " ")
                    continue
                if sym == "bodymap":  # the colour map from body 1 to body n, then its words
                    for j in range(40):
                        col = _rgb(colours[round(j / 39 * (len(colours) - 1))])
                        draw.line((x + j * k, y - 5 * k, x + j * k, y + 5 * k), fill=col, width=max(1, round(k)))
                    draw.text((x + 46 * k, y), text, fill=(60, 60, 60), font=self.small, anchor="lm")
                    continue
                self._symbol(draw, sym, x, y, grey)
                draw.text((x + 30 * k, y), text, fill=(60, 60, 60), font=self.small, anchor="lm")

    def _symbol(self, draw, sym, x, y, grey):
        k = self.k
        w = max(1, round(k))
        if sym in ("bar", "link"):
            draw.line((x, y, x + 24 * k, y), fill=grey, width=max(1, round((4 if sym == "bar" else 2.5) * k)))
        elif sym == "dot":
            draw.ellipse((x + 7 * k, y - 5 * k, x + 17 * k, y + 5 * k), fill=grey, outline=(40, 40, 40), width=w)
        elif sym == "ring":
            draw.ellipse((x, y - 6 * k, x + 24 * k, y + 6 * k), outline=grey, width=max(1, round(2 * k)))
        elif sym == "disc":
            draw.ellipse((x, y - 5 * k, x + 24 * k, y + 5 * k), fill=grey + (76,), outline=grey, width=w)
            draw.line((x + 12 * k, y, x + 22 * k, y), fill=(255, 255, 255), width=max(1, round(2 * k)))
        elif sym in ("deck", "deck_only"):
            col = _rgb(PLATFORM_COLOUR)
            draw.polygon([(x + 4 * k, y - 5 * k), (x + 26 * k, y - 5 * k), (x + 20 * k, y + 5 * k), (x - 2 * k, y + 5 * k)],
                         fill=col + (28,), outline=col + (150,), width=w)
        elif sym == "triad":
            col = _rgb(FRAME_COLOUR)
            for dx, dy in ((0, 7), (12, -5), (-9, -5)):
                draw.line((x + 12 * k, y, x + (12 + dx) * k, y + dy * k), fill=col, width=w)
        elif sym == "trace":
            col = _rgb(TRACE_COLOUR)
            for j in range(6):
                draw.line((x + 4 * j * k, y, x + 4 * (j + 1) * k, y), fill=col + (int(255 * (j + 1) / 6),), width=max(1, round(1.8 * k)))

    def _overlay(self, draw, t: float):
        k = self.k
        draw.text((10 * k, 8 * k), self.scene.name, fill=(30, 30, 30), font=self.font)
        draw.text((10 * k, 8 * k + 1.2 * self.font.size), f"t = {t:.{self.decimals}f} s", fill=(30, 30, 30), font=self.font)
        if self.scene.caption:
            draw.text((self.W * self.ss - 10 * k, 8 * k), self.scene.caption, fill=(60, 60, 60), font=self.small, anchor="ra")
        self._legend(draw)
        if self.scene.gravity:  # an arrow along ê⁰₁ in the lower left corner, above the legend
            d = self.cam.matrix[:2, 0]  # screen right/up of ê⁰₁
            H = self.H * self.ss - self.band * self.ss
            cx, cy = 34 * k, H - 34 * k
            if np.hypot(*d) < 0.2:
                draw.ellipse((cx - 4 * k, cy - 4 * k, cx + 4 * k, cy + 4 * k), outline=_rgb(FRAME_COLOUR), width=max(1, round(1.5 * k)))
            else:
                d = d / np.hypot(*d) * 20 * k
                tip = (cx + d[0], cy - d[1])
                draw.line((cx - d[0], cy + d[1], *tip), fill=_rgb(FRAME_COLOUR), width=max(1, round(2 * k)))
                back = np.array([-d[0], d[1]]) * 0.35
                for s in (1, -1):
                    side = np.array([-back[1], back[0]]) * 0.6 * s
                    draw.line((*tip, tip[0] + back[0] + side[0], tip[1] + back[1] + side[1]), fill=_rgb(FRAME_COLOUR), width=max(1, round(2 * k)))
            draw.text((cx + 14 * k, cy - 22 * k), "g", fill=_rgb(FRAME_COLOUR), font=self.font)
