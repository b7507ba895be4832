"""trusscodesign: sub-structured (TITOP/NINOP) modelling and robust co-design of flexible space trusses.

Four layers, each a subpackage whose docstring maps its modules; imports go one way only, down the list:

``study``
    the studies the notebooks run: design, sensitivity, robustness, time domain, particle-swarm co-design;
``control``
    the pointing loop, exact norms, mu bounds and the robust structured synthesis of the PMA gain;
``model``
    the sub-structured multi-port models, the LFT algebra and the uncertain spacecraft;
``infra``
    the plumbing: input checks, paths, results files and caches, versions, plotting.

Example: ``from trusscodesign.model import spacecraft``.
"""

import logging
from importlib.metadata import PackageNotFoundError, version

# the library reports progress through logging (the synthesis: a line per round at INFO); silent unless the user
# configures logging, e.g. logging.basicConfig(level=logging.INFO)
logging.getLogger(__name__).addHandler(logging.NullHandler())

try:
    __version__ = version("trusscodesign")  # one version, pyproject.toml's
except PackageNotFoundError:  # run from a checkout on the path without being installed
    __version__ = "unknown"
