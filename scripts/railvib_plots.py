"""The figures the vibration standards use, drawn one way for the live monitor and the report.

- DIN 4150-3 (structures): the peak particle velocity of each component at its dominant frequency
  against the guideline, on a log velocity axis: the residential foundation curve (Table 1 row 2,
  printed by the core: `railvib_tool din-guides`) and, for a floor, the floor values (15 mm/s
  horizontal, 20 mm/s vertical). In the free field the standard does not apply: the curve is drawn
  grey and the axes say so.
- One-third octave band levels (dB re 1e-9 m/s, ISO 1683), bars on the nominal band centres.

Nothing here computes a limit or a level: the values come from the core (din-guides, metrics)."""
import json
import math
import subprocess

import railvib_paths

COMPONENT_NAMES = ("x", "y", "z")
COMPONENT_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c")
BAR_COLOUR = "#8da0cb"
GUIDELINE_COLOUR = "black"
NOT_APPLICABLE_COLOUR = "0.65"
PPV_AXIS_MM_S = (0.01, 50.0)


class Guidelines:
    """The core's DIN guide values (railvib_tool din-guides), or why they are not there (error)."""

    def __init__(self, frequency_hz=None, limit_mm_s=None, floor_mm_s=None, din4150_2=None, error=None):
        self.frequency_hz = frequency_hz or []
        self.limit_mm_s = limit_mm_s or []
        self.floor_mm_s = floor_mm_s or {}
        self.din4150_2 = din4150_2 or {}
        self.error = error


def load_guidelines(max_hz=100.0):
    """The DIN 4150-3 residential curve and floor values, the DIN 4150-2 guide values, from the core."""
    tool = railvib_paths.find_railvib_tool()
    if tool is None:
        return Guidelines(error="railvib_tool not found (build the workspace: ./railvib setup)")
    try:
        run = subprocess.run([tool, "din-guides", "--max-hz", repr(float(max_hz))], capture_output=True, text=True,
                             timeout=60)
    except (OSError, subprocess.TimeoutExpired) as error:
        return Guidelines(error=f"railvib_tool din-guides: {error}")
    if run.returncode != 0:
        last = (run.stderr.strip().splitlines() or ["no output"])[-1]
        return Guidelines(error=f"railvib_tool din-guides failed (exit {run.returncode}): {last}")
    try:
        out = json.loads(run.stdout)
        curve = out["din4150_3_residential"]
        frequency_hz = [float(f) for f in curve["frequency_hz"]]
        limit_mm_s = [float(v) for v in curve["limit_mm_s"]]
        floors = out.get("din4150_3_floors", {})
        floor_mm_s = {k: float(floors[k]) for k in ("horizontal_mm_s", "vertical_mm_s") if k in floors}
    except (ValueError, KeyError, TypeError) as error:
        return Guidelines(error=f"railvib_tool din-guides: unexpected output ({error})")
    if not frequency_hz or len(frequency_hz) != len(limit_mm_s):
        return Guidelines(error="railvib_tool din-guides: empty or inconsistent DIN 4150-3 curve")
    return Guidelines(frequency_hz, limit_mm_s, floor_mm_s, out.get("din4150_2_residential"))


def din4150_3_axes(ax, guidelines, kind=None, fontsize=8, title="PPV (mm/s) vs DIN 4150-3 residential",
                   resolved_hz=None):
    """The guideline on ax (log PPV axis, frequency axis up to the curve's end). kind: 'free_field',
    'foundation', 'floor' or None (unknown: the foundation curve). resolved_hz: the model's resolved
    frequency; above it (shaded) a peak's frequency is not the model's to judge (not assessable)."""
    ax.set_yscale("log")
    ax.set_ylim(*PPV_AXIS_MM_S)
    applies = kind != "free_field"
    colour = GUIDELINE_COLOUR if applies else NOT_APPLICABLE_COLOUR
    if guidelines.frequency_hz:
        label = "foundation guideline" if kind != "floor" else "foundation guideline (for reference)"
        ax.plot(guidelines.frequency_hz, guidelines.limit_mm_s, color=colour, lw=1.2,
                ls="-" if kind != "floor" else ":", label=label)
        ax.set_xlim(0.0, max(guidelines.frequency_hz))
    else:
        ax.text(0.5, 0.5, "no DIN 4150-3 guideline:\n" + (guidelines.error or "?"), ha="center", va="center",
                transform=ax.transAxes, fontsize=fontsize - 1, color="#c0141c", wrap=True)
        ax.set_xlim(0.0, 100.0)
    if kind == "floor":
        for key, style, label in (("horizontal_mm_s", "--", "floor, horizontal"), ("vertical_mm_s", "-", "floor, vertical")):
            if key in guidelines.floor_mm_s:
                ax.axhline(guidelines.floor_mm_s[key], color=GUIDELINE_COLOUR, lw=1.2, ls=style, label=label)
    if resolved_hz and resolved_hz < ax.get_xlim()[1]:
        ax.axvspan(resolved_hz, ax.get_xlim()[1], color="0.9", lw=0, zorder=0,
                   label=f"above the resolved {resolved_hz:g} Hz")
    if not applies:
        ax.text(0.98, 0.04, "free field: DIN 4150-3 does not apply", transform=ax.transAxes, ha="right",
                va="bottom", fontsize=fontsize - 1, color="0.35")
    ax.set_title(title, loc="left", fontsize=fontsize)
    ax.set_xlabel("frequency (Hz)", fontsize=fontsize)
    ax.grid(True, lw=0.3, alpha=0.5, which="both")


def mark_ppv(ax, frequency_hz, ppv_mm_s, component, label=None, size=7):
    """One component's peak at its dominant frequency, in its colour (the monitor moves it live)."""
    return ax.plot([frequency_hz], [ppv_mm_s], "o", ms=size, color=COMPONENT_COLOURS[component], mec="black",
                   mew=0.8, label=label)[0]


def third_octave_floor(levels_db):
    """The bottom of a band level axis (dB): 5 dB under the lowest finite level, at most 80 dB under the
    highest (an empty band, -inf, would flatten the others). None when no level is finite."""
    finite = [float(v) for v in levels_db if v is not None and math.isfinite(float(v))]
    if not finite:
        return None, None
    top = max(finite) + 5.0
    return max(min(finite) - 5.0, top - 80.0), top


def third_octave_ticks(ax, centres_hz, positions, fontsize=7):
    """Every few band centres as tick labels under bars at `positions`."""
    step = max(1, len(centres_hz) // 8)
    ax.set_xticks(list(positions)[::step])
    ax.set_xticklabels([f"{c:g}" for c in list(centres_hz)[::step]], fontsize=fontsize)
    ax.set_xlim(min(positions) - 0.6, max(positions) + 0.6)


def third_octave_axes(ax, fontsize=8, title="1/3 octaves, dB re 1e-9 m/s"):
    ax.set_title(title, loc="left", fontsize=fontsize)
    ax.set_xlabel("band centre (Hz)", fontsize=fontsize)
    ax.grid(True, lw=0.3, alpha=0.5)


def third_octave_bars(ax, centres_hz, levels_by_component, resolved_hz=None, fontsize=8):
    """Grouped bars, one per component given ({component index: levels}), on the nominal band centres;
    bands above resolved_hz (the soil mesh's resolved frequency) shaded: the model does not resolve them."""
    import numpy as np

    all_levels = [v for levels in levels_by_component.values() for v in levels]
    bottom, top = third_octave_floor(all_levels)
    third_octave_axes(ax, fontsize)
    if bottom is None:
        ax.text(0.5, 0.5, "no level", transform=ax.transAxes, ha="center", va="center", fontsize=fontsize)
        return
    positions = np.arange(len(centres_hz), dtype=float)
    width = 0.8 / max(1, len(levels_by_component))
    for i, (component, levels) in enumerate(sorted(levels_by_component.items())):
        values = np.array([float(v) if v is not None else -np.inf for v in levels])
        values = np.where(np.isfinite(values), np.maximum(values, bottom), bottom)
        ax.bar(positions - 0.4 + width * (i + 0.5), values - bottom, bottom=bottom, width=width,
               color=COMPONENT_COLOURS[component], label=f"v_{COMPONENT_NAMES[component]}")
    if resolved_hz:
        above = [p for p, c in zip(positions, centres_hz) if c > resolved_hz * 2 ** (1 / 6)]
        if above:
            ax.axvspan(min(above) - 0.5, max(above) + 0.5, color="0.88", lw=0, zorder=0,
                       label=f"above the resolved {resolved_hz:g} Hz")
    ax.set_ylim(bottom, top)
    third_octave_ticks(ax, centres_hz, positions, fontsize - 1)
    ax.set_ylabel("L_v (dB)", fontsize=fontsize)


def fit_title(fig, text, fontsize=10, y=None):
    """A figure title that fits the figure: wrapped at word boundaries until its rendered width is within
    the figure's (a long title was cut at both edges). Returns the number of lines."""
    import textwrap

    renderer = fig.canvas.get_renderer()
    width_px = fig.get_figwidth() * fig.dpi
    chars = max(20, len(text))
    while True:
        wrapped = "\n".join(textwrap.wrap(text, chars)) if chars < len(text) else text
        title = fig.suptitle(wrapped, fontsize=fontsize, **({"y": y} if y is not None else {}))
        if title.get_window_extent(renderer).width <= 0.98 * width_px or chars <= 20:
            return wrapped.count("\n") + 1
        chars = int(chars * 0.85)


def save_gif(fig, update, frame_count, path, fps=10, dpi=80):
    """An animated GIF of fig: update(k) changes the artists for frame k (data, titles), never their
    sizes. The layout (constrained or tight) is computed once, on the first frame, then kept; each frame
    is drawn once. (matplotlib's FuncAnimation with PillowWriter laid the figure out and drew it twice
    per frame: 22 s for a 39-frame section animation, where this takes a fraction.)"""
    from PIL import Image

    fig.set_dpi(dpi)
    images = []
    for k in range(frame_count):
        update(k)
        fig.canvas.draw()
        if k == 0:
            fig.set_layout_engine("none")  # keeps the positions the first draw gave the axes
        width, height = fig.canvas.get_width_height()
        images.append(Image.frombuffer("RGBA", (width, height), bytes(fig.canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
                      .convert("RGB"))
    if not images:
        raise ValueError("save_gif: no frames")
    images[0].save(path, save_all=True, append_images=images[1:], duration=int(round(1000.0 / fps)), loop=0)
