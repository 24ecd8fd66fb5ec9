"""Visual tools: live view, animations, plots, behaviour-tree diagrams, sensor monitor.

Each tool lives in its own module and imports matplotlib, Pillow, imageio or rich only
when it is used, so ``import puckboard.viz`` costs nothing. Every tool reads what every
backend provides (blackboard keys and the scene), so each works the same with the
embedded simulator, CoppeliaSim and a real e-puck. Recorded runs, which the tools draw
after the fact, are :mod:`puckboard.recording`; ``puckboard.viz.hooks.attach`` wires the
tools to a run. In Jupyter, :func:`puckboard.web.show_replay` shows a recorded run in the
web view's player, inline.
"""
