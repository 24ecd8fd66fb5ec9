"""The ``estimation`` suite: how good is the odometry estimate, against the simulator's truth.

The suite (:mod:`.suite`) runs the two-robot pass (its whole 120 s) with the scene's
controllers and with the stock controllers (with which the two robots collide), and three
laps of ``line-follow`` on the embedded simulator, with and without wheel-speed noise, for
a few seeds, and reports per robot the position and heading error of the estimate at the
end and at worst, and how often the true pose lay inside the estimate's 95 % ellipse.
Each run (:mod:`.trial`) has three estimates side by side on the very same simulation:

``encoders``
    the :class:`~puckboard.estimation.OdometrySource` end to end, on the blackboard,
    fed by the simulated step counters. As on a real e-puck, the stepper motors make
    exactly the commanded steps and the counters count them; how far the body actually
    moves differs by the wheels' slip on the floor (the scene's wheel-speed noise) and by
    contacts (a robot pushed along a wall or an obstacle while its wheels turn). Neither
    is visible to odometry: this is the drift students meet on a real robot.
``encoders + gyro``
    the same source fused with the simulated gyro (the e-puck2's), which measures how
    fast the body actually turned: slip and contacts that fool the counters do not fool
    it. The gyro is ideal unless ``gyro_noise`` (σ, rad/s) or ``gyro_bias`` (rad/s) is
    given; the source learns a bias only while the wheels stand still (``settle``), so
    without a standstill a bias goes straight into the heading.
``axle +1 mm``
    the encoder filter with an axle 1 mm longer than the simulated robot's (54 instead
    of 53 mm; published values range from 51 to 56.5 mm): an uncalibrated robot.

Every estimate starts at the true start pose (the start jitter is not counted as
odometry error) and is compared with the ground truth of the same instant. The suite
also measures the IR filter on the simulator's sensor model (:mod:`.proximity`) and what
each filter costs per call next to its alternatives (:mod:`.costs`); :mod:`.plot` draws
an estimate against the truth.

Run it with ``puckboard bench --suite estimation`` (``--plot FILE`` also draws the
estimate against the truth with covariance ellipses; ``puckboard bench --help`` lists the
suite's other options).
"""
