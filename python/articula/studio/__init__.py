"""Articula Studio: the arm in 3D in the browser (docs/studio.md). `articula-studio` or
`make studio` starts it; `python -m articula.studio --help` says how."""
