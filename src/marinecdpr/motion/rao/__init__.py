"""Response amplitude operators (RAOs): the package's public face (being split by subject;
for now the whole of the former ``motion/rao.py`` lives in :mod:`.capytaine`)."""

from marinecdpr.motion.rao.capytaine import *  # noqa: F401,F403
from marinecdpr.motion.rao.capytaine import __all__, check_positive  # noqa: F401
