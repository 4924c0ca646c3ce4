"""GoPiGo driver: hardware backends, motor map, simulated motors."""
