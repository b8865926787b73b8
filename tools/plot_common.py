"""plot_common.py: how every plot script of tools/ starts — matplotlib drawing into files (its
Agg backend), with the other modules the script needs.

    from plot_common import pyplot
    plt, h5py, np = pyplot(__file__, "h5py", "numpy")

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
