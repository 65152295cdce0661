# %% [markdown]
# # Load against contact area of a measured surface, from Python
#
# An instrument's height map (a Zygo MetroPro `.dat` file of a real surface,
# 640 x 480 points at 1.1 µm) read with `height-map`, a 256 x 256 window of it
# (`crop`), its statistics and PSD from `surface`, then two
# contact models with the paper's EPDM: boundary elements on the map itself
# (`bem`) and Persson's theory on its PSD (`persson`). Every call is a
# hypercontact stage; parameters, defaults and error messages are those of a
# pipeline's `with:` block (`help(hypercontact.stages.bem)` lists them).
#
# Run it as a script (`python examples/python/contact_curve.py [out.png]`)
# or cell by cell in a notebook.

# %%
import sys
from pathlib import Path

import matplotlib

if __name__ == "__main__" and "ipykernel" not in sys.modules:
    matplotlib.use("Agg")  # a script writes the figure; a notebook shows it
import matplotlib.pyplot as plt

import hypercontact
from hypercontact import stages

REPO = Path(__file__).resolve().parents[2] if "__file__" in globals() else Path.cwd()
MAP = REPO / "data" / "reference" / "topography" / "metropro-1.dat"

# %% The measured map, as the instrument wrote it.
height = stages.height_map(path=MAP)
print(height)  # Field(nx x ny, dx_m=..., dy_m=...)

# %% A window, so the BEM solve takes seconds (the whole map works too).
window = stages.crop(surface=height, x0=0, y0=0, nx=256, ny=256)["height"]

# %% Statistics and PSD on the measured grid. The paper's 20 µm filter would
# leave a dozen points of this window, so it is switched off.
surface = stages.surface(height=window, resolution_m=0, reference="percentile")
stats = surface["stats"]
print(stats.select(["sigma_m", "rms_slope", "hurst_radial", "hurst_radial_r2"]))
print("units:", {c: stats.units.get(c, "") for c in ["sigma_m", "rms_slope"]})

# %% The material (the paper's EPDM, Ogden), then both contact models.
material = stages.material_preset()
bem = stages.bem(surface=surface["height"], material=material, model="linear",
                 steps=20, max_area_fraction=0.5, map_fractions=[0.1, 0.5])
persson = stages.persson(psd=surface["psd"], stats=surface["stats"], material=material,
                         model="linear", max_area_fraction=0.5)

# %% Load against contact area, both models on one chart.
fig, ax = plt.subplots(figsize=(5.5, 4))
for name, response in [("BEM (map)", bem["response"]), ("Persson (PSD)", persson["response"])]:
    curve = response.filter(response["load_n"] > 0)
    ax.plot(curve["load_norm"], curve["area_fraction"], label=name)
ax.set_xscale("log")
ax.set_xlabel("normalised load F / (E0* A0)")
ax.set_ylabel("contact area A / A0")
ax.set_title(f"{MAP.name}: linear elastic EPDM")
ax.legend()
fig.tight_layout()

if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("contact_curve.png")
    fig.savefig(out, dpi=150)
    print(f"figure: {out}")
