"""The sensors that ship with vwg, one module each: ``laser`` (gLaser), ``kinect`` (gKinect, a depth
camera read as a laser), ``camera`` (gCamera, AprilTag markers). They are registered by the
``vwg.sensors`` entry points of vwg's pyproject.toml, as a plugin's sensors are."""
