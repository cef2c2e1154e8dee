"""An example plugin of vwg, found by its entry points only (pyproject.toml): the sensor ``sonar`` (a
ring of sonar beams), the platform ``kinematic`` (robots moved exactly as they are told, written in
Python, with no physics) and the decider ``wall-follower`` (follows the wall on its right until the way
to its goal is clear). Nothing here registers itself: installing the package is what makes vwg see it.
"""

__version__ = "0.1"
