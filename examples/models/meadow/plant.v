/* View file: cpfg reads the angle and widths from here, not from plant.l. */
angle factor: 16
initial line width: 0.25
line width increment: 0.05
tropism direction: 0 1 0
initial elasticity: 0.05
