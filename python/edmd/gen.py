"""Ready-made systems: the generators of ``edmd gen``, returning a :class:`edmd.Simulation`.

Each function takes the options ``edmd gen KIND`` takes for that kind (as keyword arguments,
``None`` for the kind's documented default) and a ``seed``; the same seed gives the same
system as ``edmd gen KIND --seed S``, bit for bit. Bad values raise ``ValueError`` with the
command's message. ``rule`` ("elastic" or "swap") and ``multi`` are the run options of the
simulation returned; ``restitution`` (every kind) makes its collisions inelastic, as
``Simulation.set_restitution`` takes it (``edmd gen KIND --restitution ...``); ``gravity=G``
(every kind) puts the system in a uniform field of acceleration ``G`` along the last axis (y in
2D, z in 3D; negative pulls towards 0), which then has walls (``edmd gen KIND --gravity G``;
fluids and mixtures keep periodic sides unless ``boundary="walls"``); ``shear=RATE`` (fluids
and mixtures in periodic boxes) shears them with Lees-Edwards boundaries, the velocities on the
streaming profile (``edmd gen KIND --shear RATE``). A value of the wrong type (a str for a
number, a bool or a float for a count) raises ``TypeError`` naming the argument.

Example::

    import edmd
    sim = edmd.gen.fluid(n=500, packing=0.4, dim=3, seed=2)   # a melted hard-sphere fluid
    sim = edmd.gen.mixture(n=400, size_ratio=1.4, fraction_large=0.5, seed=3)
    sim = edmd.gen.fluid(n=500, packing=0.3, well=1.5, seed=4)   # a square-well fluid
    sim = edmd.gen.fluid(n=500, packing=0.3, restitution=0.9, seed=5)   # a granular gas
    sim = edmd.gen.fluid(n=500, packing=0.3, gravity=-1.0, seed=6)      # a column in a field
    sim = edmd.gen.fluid(n=500, packing=0.3, shear=0.2, seed=7)         # in simple shear flow
    sim = edmd.gen.ring(n=400, tau=0.25, restitution={"all": {"bridges": 0.01}})  # a ring patch
    sim = edmd.gen.sheets(n=1000, seed=1)   # a water bag of self-gravitating sheets
"""

from edmd import _check
from edmd._edmd import _generate as _compiled_generate

# The options whose values are numbers, whole numbers, text and flags (`edmd gen`'s).
_REAL = ("radius", "speed", "mass", "kt", "packing", "angle", "impact", "region", "big_radius",
         "big_mass", "size_ratio", "fraction_large", "spread", "well", "shoulder", "depth",
         "gravity", "shear", "tau", "omega", "dispersion", "height", "width", "coupling")


def _generate(kind, **options):
    """Checks the options' types and ranges (naming them), then makes the system in Rust."""
    for name in _REAL:
        if name in options:
            options[name] = _check.real(name, options[name])
    if "n" in options:
        options["n"] = _check.whole("n", options["n"], -(2**63), 2**63 - 1)
    if options.get("seed", 1) is None:
        raise TypeError("seed: expected a whole number, got None")
    options["seed"] = _check.whole("seed", options.get("seed", 1), 0, 2**64 - 1)
    if "dim" in options:
        options["dim"] = _check.whole("dim", options["dim"], -(2**63), 2**63 - 1)
    for name in ("boundary", "rule"):
        if name in options:
            _check.text(name, options[name])
    if "rule" in options and options["rule"] is None:
        raise TypeError("rule: expected 'elastic' or 'swap', got None")
    if "multi" in options:
        _check.flag("multi", options["multi"])
    try:
        return _compiled_generate(kind, **options)
    except ValueError as e:
        named = _check.naming_the_argument(e, {k for k, v in options.items() if v is not None})
        if named is None:
            raise
        raise named from None

__all__ = [
    "single",
    "head_on",
    "angled",
    "one_red",
    "lattice",
    "diffusion1",
    "diffusion2",
    "dense",
    "brownian",
    "fluid",
    "mixture",
    "ring",
    "sheets",
]


def single(*, radius=None, speed=None, mass=None, seed=1, rule="elastic", restitution=None,
           gravity=None):
    """One disc bouncing in the unit box with walls (``edmd gen single``)."""
    return _generate("single", seed=seed, radius=radius, speed=speed, mass=mass, rule=rule,
                     restitution=restitution, gravity=gravity)


def head_on(*, radius=None, speed=None, mass=None, seed=1, rule="elastic", restitution=None,
            gravity=None):
    """Two discs meeting head-on (``edmd gen head-on``)."""
    return _generate("head-on", seed=seed, radius=radius, speed=speed, mass=mass, rule=rule,
                     restitution=restitution, gravity=gravity)


def angled(*, radius=None, speed=None, mass=None, angle=None, impact=None, seed=1, rule="elastic",
           restitution=None, gravity=None):
    """Two discs whose paths cross at ``angle`` degrees with impact parameter ``impact`` (a
    fraction of the contact distance) (``edmd gen angled``)."""
    return _generate(
        "angled", seed=seed, radius=radius, speed=speed, mass=mass, angle=angle,
        impact=impact, rule=rule, restitution=restitution, gravity=gravity,
    )


def one_red(*, n=None, radius=None, speed=None, seed=1, rule="elastic", restitution=None,
            gravity=None):
    """A crowd of ``n`` discs and one red one (``edmd gen one-red``)."""
    return _generate("one-red", seed=seed, n=n, radius=radius, speed=speed, rule=rule,
                     restitution=restitution, gravity=gravity)


def lattice(*, n=None, radius=None, mass=None, kt=None, seed=1, rule="elastic",
            restitution=None, gravity=None):
    """``n`` discs on a lattice with thermal velocities at temperature ``kt``
    (``edmd gen lattice``)."""
    return _generate("lattice", seed=seed, n=n, radius=radius, mass=mass, kt=kt, rule=rule,
                     restitution=restitution, gravity=gravity)


def diffusion1(*, n=None, radius=None, speed=None, region=None, seed=1, rule="elastic",
               restitution=None, gravity=None):
    """``n`` discs starting in a central square of side ``region`` (``edmd gen diffusion1``)."""
    return _generate(
        "diffusion1", seed=seed, n=n, radius=radius, speed=speed, region=region, rule=rule,
        restitution=restitution, gravity=gravity,
    )


def diffusion2(*, n=None, radius=None, mass=None, kt=None, seed=1, rule="elastic",
               restitution=None, gravity=None):
    """Two species, ``n`` discs each, starting on either side of the box
    (``edmd gen diffusion2``)."""
    return _generate("diffusion2", seed=seed, n=n, radius=radius, mass=mass, kt=kt, rule=rule,
                     restitution=restitution, gravity=gravity)


def dense(*, n=None, packing=None, mass=None, kt=None, seed=1, rule="elastic", restitution=None,
          gravity=None):
    """A dense system of ``n`` discs at packing fraction ``packing`` (``edmd gen dense``)."""
    return _generate("dense", seed=seed, n=n, packing=packing, mass=mass, kt=kt, rule=rule,
                     restitution=restitution, gravity=gravity)


def brownian(*, n=None, radius=None, mass=None, big_radius=None, big_mass=None, kt=None,
             seed=1, rule="elastic", restitution=None, gravity=None):
    """A big disc among ``n`` small ones (``edmd gen brownian``)."""
    return _generate(
        "brownian", seed=seed, n=n, radius=radius, mass=mass, big_radius=big_radius,
        big_mass=big_mass, kt=kt, rule=rule, restitution=restitution, gravity=gravity,
    )


def fluid(*, n=None, packing=None, dim=2, boundary=None, well=None, shoulder=None, depth=None,
          kt=None, seed=1, rule="elastic", multi=False, species=None, reactions=None,
          restitution=None, gravity=None, shear=None):
    """A melted fluid of ``n`` equal discs (``dim=2``) or spheres (``dim=3``) at packing
    fraction ``packing``, with "periodic" (default) or "walls" ``boundary``
    (``edmd gen fluid``). ``dim=1`` makes hard rods on a line (length 1, mass 1, evenly
    spaced, packing 0.5 by default and below 1): arrays of shape ``(N, 1)``; a line takes no
    ``shear``, and its ``gravity`` is along x.

    ``well=L`` makes it a square-well fluid: a well of depth ``depth`` (1 when None) out to
    ``L`` diameters (``edmd gen fluid --well L``); ``shoulder=L`` a square-shoulder fluid of
    height ``depth``. ``L`` is above 1 and at most 100. The potential is
    ``sim.potential``, ``{(0, 0): [(L * diameter, -depth)]}`` for a well. ``kt`` scales the
    velocities to temperature ``kt`` (1 when None). Wells and shoulders need the elastic rule
    and binary collisions (``multi=False``).

    ``species=(f0, f1, ...)`` gives the discs species 0, 1, ... in those number fractions
    (summing to 1; ``edmd gen fluid --species F0,F1,...``): species k gets round(N f_k) discs,
    placed at random (seeded by ``seed``), and a colour of its own. ``reactions`` are reaction
    rules, as ``Simulation.set_reactions`` takes them (``edmd gen fluid --reaction RULE``),
    their draws seeded by 1 (as ``edmd run`` runs the file ``edmd gen`` writes; another seed:
    ``set_reactions(**{**sim.reactions, "seed": S})``, or the dict form ``{"rules": [...],
    "seed": S}``). Rules do not go with a well or a shoulder.

    ``restitution`` makes collisions inelastic, as ``Simulation.set_restitution`` takes it (a
    coefficient for every pair, or ``{"all": ..., "pairs": {...}, "walls": e, "tc": t}``;
    ``edmd gen fluid --restitution ...``); it does not go with a well, a shoulder or reaction
    rules. Every generator takes it.

    ``gravity=G`` puts the fluid in a uniform field of acceleration ``G`` along the last axis
    (``edmd gen fluid --gravity G``): that axis gets walls, the others stay periodic unless
    ``boundary="walls"``; ``sim.gravity`` is then ``{"axis": dim - 1, "g": G}``. It does not go
    with a well or a shoulder, and inelastic collisions in a field need the TC model
    (``restitution={..., "tc": t}``, t > 0). Every generator takes it.

    ``shear=RATE`` shears the fluid with Lees-Edwards boundaries (``edmd gen fluid --shear
    RATE``): the images across y slide along x at ``RATE * L_y`` from an offset of 0, and
    ``RATE * (y - L_y / 2)`` is added to each x velocity so that the run starts in steady flow;
    ``sim.shear`` is then ``(RATE, 0.0)``. It needs a periodic box and does not go with a well,
    a shoulder or ``gravity``; ``mixture`` takes it too.

    >>> sim = edmd.gen.fluid(n=1000, packing=0.5, seed=1)
    >>> sw = edmd.gen.fluid(n=500, packing=0.3, well=1.5, kt=1.2, seed=1)
    >>> ab = edmd.gen.fluid(n=1000, packing=0.3, species=(0.5, 0.5),
    ...                     reactions=["0 + 1 -> 2 + 2 activation 1"], seed=1)
    >>> granular = edmd.gen.fluid(n=1000, packing=0.3, boundary="walls", seed=1,
    ...                           restitution={"all": 0.9, "walls": 0.8, "tc": 1e-4})
    >>> column = edmd.gen.fluid(n=1000, packing=0.3, gravity=-1.0, seed=1)
    >>> flow = edmd.gen.fluid(n=1000, packing=0.3, shear=0.5, restitution=0.8, seed=1)
    >>> rods = edmd.gen.fluid(n=1000, packing=0.8, dim=1, seed=1)
    """
    return _generate(
        "fluid", dim=dim, seed=seed, n=n, packing=packing, boundary=boundary, well=well,
        shoulder=shoulder, depth=depth, kt=kt, rule=rule, multi=multi, species=species,
        reactions=reactions, restitution=restitution, gravity=gravity, shear=shear,
    )


def mixture(*, n=None, packing=None, dim=2, boundary=None, size_ratio=None,
            fraction_large=None, spread=None, seed=1, rule="elastic", multi=False,
            restitution=None, gravity=None, shear=None):
    """A melted mixture: binary (``size_ratio`` large/small diameters, ``fraction_large`` by
    number) or polydisperse (diameters uniform in 1 +- ``spread``) (``edmd gen mixture``);
    ``shear=RATE`` as in :func:`fluid`."""
    return _generate(
        "mixture", dim=dim, seed=seed, n=n, packing=packing, boundary=boundary,
        size_ratio=size_ratio, fraction_large=fraction_large, spread=spread, rule=rule,
        multi=multi, restitution=restitution, gravity=gravity, shear=shear,
    )


def ring(*, n=None, tau=None, omega=None, dispersion=None, height=None, dim=3, seed=1,
         rule="elastic", multi=False, restitution=None):
    """A patch of a planetary ring (``edmd gen ring``): ``n`` equal particles (400 when None)
    of radius 0.5 (diameter 1) and mass 1 at random in a square patch, periodic along x (the
    orbit) and y (radial), at dynamical optical depth ``tau`` (``n pi r^2 / (L_x L_y)``, 0.25
    when None; at most 0.5 in 2D and 2 in 3D), with ``dim=3`` (the default) a box ``height``
    diameters high (60 when None) between walls along z. The velocities are the Keplerian
    flow ``-1.5 * omega * (y - L_y / 2)`` along x plus Gaussian deviations of ``dispersion``
    times ``omega`` times the diameter per axis (2 when None), and the simulation is a ring
    patch at orbital frequency ``omega`` (1 when None): ``sim.ring`` is ``omega``, as after
    ``sim.set_ring(omega)``.

    ``restitution`` makes collisions inelastic, as ``Simulation.set_restitution`` takes it; a
    constant coefficient below 1 needs the TC model (``{"all": e, "tc": t}``, t > 0, e.g.
    ``1e-3 / omega``), Bridges' law (``{"all": {"bridges": v_c}}``) none.

    >>> patch = edmd.gen.ring(n=400, tau=0.25, restitution={"all": 0.5, "tc": 1e-3}, seed=1)
    >>> patch.ring
    1.0
    >>> flat = edmd.gen.ring(n=300, dim=2, restitution={"all": {"bridges": 0.01}})
    """
    return _generate(
        "ring", dim=dim, seed=seed, n=n, tau=tau, omega=omega, dispersion=dispersion,
        height=height, rule=rule, multi=multi, restitution=restitution,
    )


def sheets(*, n=None, width=None, speed=None, coupling=None, radius=None, seed=1):
    """A water bag of self-gravitating sheets (``edmd gen sheets``): ``n`` sheets (1000 when
    None) of mass 1 on a line, positions uniform in ``[-width, width]`` (1 when None) and
    velocities in ``[-speed, speed]`` (1 when None) about the middle of the line, the centre
    of mass at rest there, between walls 1.25 times as far from the middle as the energy lets
    a sheet go, or as 16 bag widths if that is nearer. The sheets are rods of half-length ``radius`` (1e-7 when None), and the
    simulation is under self-gravity of strength ``coupling`` (``1 / n`` when None, so that
    the whole mass pulls with 1): ``sim.self_gravity`` is ``coupling``, as after
    ``sim.set_self_gravity(coupling)``. With the defaults the bag starts in virial
    equilibrium, ``2K = U`` (``speed**2 = width * coupling * n``).

    >>> bag = edmd.gen.sheets(n=200, seed=1)
    >>> bag.self_gravity
    0.005
    >>> bag.run(until=10.0)
    """
    return _generate(
        "sheets", dim=1, seed=seed, n=n, width=width, speed=speed, coupling=coupling,
        radius=radius,
    )
