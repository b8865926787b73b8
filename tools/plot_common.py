"""plot_common.py: how every plot script of tools/ starts — matplotlib drawing into files (its
Agg backend), with the other modules the script needs.

    from plot_common import pyplot
    plt, h5py, np = pyplot(__file__, "h5py", "numpy")

Axes carry the units of what they show: `labelled(name, unit_of(dataset))` reads the `unit`
attribute noether writes on every dataset ("t [s]", "energy [kg m^2/s^2]"; "t [T]" in a scene
of its own units); `save(fig, path)` prints the axis labels before writing the file.

A module that does not import ends the script with exit status 3 and the names on stderr:
`noether ... --plot` (apps/noether/plot.cpp) runs the scripts with the PATH's python3 and, when
that one lacks them, with Debian's /usr/bin/python3. The scripts find this file beside them
(a script's folder is on Python's path), where they are run from and where they are installed."""
import importlib
import sys


def pyplot(script, *modules):
    """matplotlib.pyplot on the Agg backend, then each named module, in order; or exit 3."""
    try:
        loaded = [importlib.import_module(name) for name in modules]
        import matplotlib
    except ImportError:  # exit 3: the driver then tries Debian's /usr/bin/python3
        needed = ", ".join(list(modules) + ["matplotlib"])
        sys.stderr.write(f"{script}: {needed} {'is' if not modules else 'are'} needed by {sys.executable}\n")
        sys.exit(3)
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return (plt, *loaded) if modules else plt


def unit_of(dataset):
    """The `unit` attribute noether writes on a dataset ("s", "km/h", "T"), or "" when it has none."""
    unit = dataset.attrs.get("unit", "")
    return unit.decode() if isinstance(unit, bytes) else str(unit)


def labelled(name, unit):
    """An axis label with its unit: "t [s]"; the name alone for a dimensionless quantity."""
    return f"{name} [{unit}]" if unit else name


def save(fig, path, dpi=90):
    """Writes the figure, after printing its axis labels on one line ("axes  t [s] | libration
    angle [deg]"): what the plot shows, in which units, readable without the picture."""
    labels = [label for ax in fig.axes for label in (ax.get_xlabel(), ax.get_ylabel()) if label]
    print(f"{'axes':<33}{' | '.join(labels)}")
    fig.savefig(path, dpi=dpi)
