"""Locomotion toward a light in PyBullet: the lower agent, the body's pose, the Gymnasium env."""
