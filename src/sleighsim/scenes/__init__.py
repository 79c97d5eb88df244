"""Scenes: one module per analysis stage; each function takes its config block (and the paths
of the datasets it reads, by role) and returns one Dataset. Each module declares the scene kinds it
computes (:class:`sleighsim.scenes.kind.SceneKind`) beside their functions; :mod:`sleighsim.scenes.catalog`
collects them and runs a scene of any kind."""
