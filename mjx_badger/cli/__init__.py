"""The command line: one module per group of commands, each command a dataclass that parses and checks its
input before anything compiles and then calls one function of the layer that owns the work (main: the commands by
name, `main`). It may import everything below it."""
