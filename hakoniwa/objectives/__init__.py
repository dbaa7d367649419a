"""The built-in objectives, one module each (`hakoniwa.wire.objective.BUILT_IN` names them): what ends a test,
what makes it a success and what it costs. A module here gives the physics' task and the controller's judging
of the same objective, so it sits above the physics and below the controller."""
