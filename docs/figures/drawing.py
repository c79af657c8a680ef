"""Drawing helpers shared by the figures of docs/architecture.md (see make_figures.py)."""
import matplotlib

matplotlib.use("Agg")
from matplotlib.patches import Circle, FancyArrowPatch, FancyBboxPatch  # noqa: E402

DPI = 110


def box(ax, x, y, w, h, face, edge="#444444", lw=1.0, radius=0.02):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle=f"round,pad=0,rounding_size={radius}", fc=face, ec=edge,
                                lw=lw))


class Graph:
    """Node boxes and labelled topic arrows on one axis."""

    def __init__(self, ax):
        self.ax, self.pos = ax, {}

    def node(self, name, x, y, colour="#dfeaf7", w=None, text=None):
        w = w or max(1.5, 0.105 * len(text or name) + 0.3)
        self.pos[name] = (x, y, w)
        box(self.ax, x - w / 2, y - 0.28, w, 0.56, colour, radius=0.08)
        self.ax.text(x, y, text or name, ha="center", va="center", fontsize=8.5, weight="bold")

    def edge(self, a, b, label, rad=0.0, dy=0.0, colour="#333333", style="-|>", frac=0.5, side_a=None, side_b=None,
             off=0.0):
        (xa, ya, wa), (xb, yb, wb) = self.pos[a], self.pos[b]
        pa = self.anchor(xa, ya, wa, xb, yb, side_a)
        pb = self.anchor(xb, yb, wb, xa, ya, side_b)
        pa, pb = (pa[0], pa[1] + off), (pb[0], pb[1] + off)  # off: two arrows between the same boxes
        self.ax.add_patch(FancyArrowPatch(pa, pb, arrowstyle=style, mutation_scale=11, lw=1.0, color=colour,
                                          connectionstyle=f"arc3,rad={rad}", shrinkA=1, shrinkB=1))
        # The label sits on the arc (matplotlib's arc3: a quadratic Bezier through this control point).
        cx = (pa[0] + pb[0]) / 2 + rad * (pb[1] - pa[1])
        cy = (pa[1] + pb[1]) / 2 - rad * (pb[0] - pa[0])
        t = frac
        mx = (1 - t) ** 2 * pa[0] + 2 * t * (1 - t) * cx + t * t * pb[0]
        my = (1 - t) ** 2 * pa[1] + 2 * t * (1 - t) * cy + t * t * pb[1] + dy
        self.ax.text(mx, my, label, ha="center", va="center", fontsize=7.2, color=colour,
                     bbox=dict(fc="white", ec="none", pad=0.6, alpha=0.85))

    @staticmethod
    def anchor(x, y, w, tx, ty, side):
        side = side or ("r" if tx > x + w / 2 else "l" if tx < x - w / 2 else "t" if ty > y else "b")
        return {"r": (x + w / 2, y), "l": (x - w / 2, y), "t": (x, y + 0.28), "b": (x, y - 0.28)}[side]


def axes_arrows(ax, x, y, vx, vy, names, colours=("#cc2222", "#228822"), scale=0.25, fs=8):
    """Two axis arrows from (x, y) along (vx[0], vy[0]) and (vx[1], vy[1]) with their names."""
    for (dx, dy), name, c in zip(zip(vx, vy), names, colours):
        ax.annotate("", (x + scale * dx, y + scale * dy), (x, y),
                    arrowprops=dict(arrowstyle="-|>", color=c, lw=1.6, mutation_scale=10))
        ax.text(x + 1.2 * scale * dx, y + 1.2 * scale * dy, name, color=c, fontsize=fs, ha="center",
                va="center", weight="bold")


def out_of_page(ax, x, y, name, r=0.035, into=False, colour="#2244cc", fs=8, dx=0.07):
    ax.add_patch(Circle((x, y), r, fill=False, ec=colour, lw=1.3))
    if into:
        ax.plot([x - r * 0.7, x + r * 0.7], [y - r * 0.7, y + r * 0.7], color=colour, lw=1.1)
        ax.plot([x - r * 0.7, x + r * 0.7], [y + r * 0.7, y - r * 0.7], color=colour, lw=1.1)
    else:
        ax.add_patch(Circle((x, y), r * 0.3, color=colour))
    ax.text(x + dx, y, name, color=colour, fontsize=fs, va="center", weight="bold")
