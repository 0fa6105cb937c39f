"""The OpenISS SDK adapters: NiTE2 (`openiss-nite`) and Nuitrack (`openiss-nuitrack`).

Each drives its middleware when the runtime is installed and can see the performer, and
otherwise runs the open engine in that middleware's mode, saying once which one runs.
"""
