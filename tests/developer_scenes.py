"""The developer scenes every real-scene test runs on (all of ../shared/data/stereo).

A module of its own, not ``conftest``: with several test folders collected at once, a
``from conftest import ...`` finds whichever folder's ``conftest`` was imported first.
"""

SCENES = ("tsukuba", "venus", "motorcycle", "cloth3", "reindeer", "wood2")
