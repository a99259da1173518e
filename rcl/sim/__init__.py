"""The simulated R-E Robot board: chips, motors, robot pose, virtual clock."""
