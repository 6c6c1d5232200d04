"""The robot's own senses and what it makes of them: the IMU and encoders with their noise (sensors),
the reading every estimator takes (reading), the thesis's Kalman and integration estimators and the registry of all
(estimators), the learned estimator as it runs (learned) and its fit (fit). It may import core, robot, agents and
tasks."""
