"""The planar multibody model: elements, bodies, joints, loads and the system.

* :mod:`.elements` — rigid elements and their mass properties (Eqs. 12-13);
* :mod:`.bodies` — rigid bodies made of elements, with named points;
* :mod:`.joints` — one class per joint kind (pin, rail, slider, rolling, ...),
  each owning its scene keys, reactions and constraint equations;
* :mod:`.loads` — gravity, forces, couples, springs and dampers;
* :mod:`.system` — coordinates, placement of every body, one validation pass
  and the kinematics of every point.
"""
