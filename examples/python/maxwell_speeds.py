# %% [markdown]
# # Speeds in a hard-disc gas: the Maxwell-Boltzmann law
#
# A notebook-style example for students (run it as a script, or cell by cell in VS Code or
# Jupyter: each `# %%` starts a cell). We make a gas of hard discs, let it collide, and compare
# the speeds with the Maxwell-Boltzmann law, which in two dimensions reads
#
#     p(v) = (m v / kT) exp(-m v^2 / 2kT)
#
# Nothing in the simulation puts this law in: the discs only collide elastically.

# %%
import matplotlib

matplotlib.use("Agg")  # write a file; drop this line in a notebook to see the figure inline
import matplotlib.pyplot as plt
import numpy as np

import edmd

# %% [markdown]
# ## A fluid
# `edmd.gen.fluid` places discs on a lattice and melts it. Here: 2000 discs covering 30% of a
# periodic box.

# %%
sim = edmd.gen.fluid(n=2000, packing=0.3, seed=1)
print(sim)

# %% [markdown]
# ## Make every disc start at the same speed
# To see the law emerge, give every disc the same speed in a random direction, then let the
# discs collide.

# %%
rng = np.random.default_rng(1)
speed = np.sqrt((sim.velocities**2).sum(axis=1).mean())  # keep the energy
angle = rng.uniform(0, 2 * np.pi, sim.n)
sim.velocities = speed * np.column_stack([np.cos(angle), np.sin(angle)])
print("speeds now:", np.unique(np.round(np.linalg.norm(sim.velocities, axis=1), 12)))

# %%
sim.run(until=20.0)
print(sim.stats["disc_disc"] / sim.n, "collisions per disc")

# %% [markdown]
# ## Histogram against the law
# The temperature is the mean kinetic energy per disc: kT = <m v^2> / 2 in two dimensions.

# %%
v = np.linalg.norm(sim.velocities, axis=1)
m = sim.masses
kt = (m * v**2).mean() / 2
x = np.linspace(0, v.max() * 1.1, 200)
law = (m.mean() * x / kt) * np.exp(-m.mean() * x**2 / (2 * kt))

fig, ax = plt.subplots(figsize=(6, 4))
ax.hist(v, bins=40, density=True, alpha=0.6, label=f"{sim.n} discs at t = {sim.time:g}")
ax.plot(x, law, label="Maxwell-Boltzmann (2D)")
ax.set_xlabel("speed v")
ax.set_ylabel("probability density")
ax.legend()
fig.tight_layout()
fig.savefig("maxwell_speeds.png", dpi=120)
print("figure written to maxwell_speeds.png")

# %% [markdown]
# ## Questions
# 1. Run for a shorter time (`until=0.5`): how far is the histogram from the law?
# 2. The engine measures this too: `sim.measure("speeds", every=1.0)`, then
#    `sim.results()["speeds"]` gives the Kolmogorov-Smirnov test against the law.
# 3. Try spheres: `edmd.gen.fluid(n=2000, packing=0.3, dim=3)`. What is the law in 3D?
