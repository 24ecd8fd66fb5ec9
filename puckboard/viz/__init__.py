"""Visual tools: live view, animations, plots, behaviour-tree diagrams, sensor monitor.

Each tool lives in its own module and imports matplotlib, Pillow, imageio or rich only
when it is used, so ``import puckboard.viz`` costs nothing. Every tool reads what every
backend provides (blackboard keys and the scene), so each works the same with the
embedded simulator, CoppeliaSim and a real e-puck. Recorded runs are in
:mod:`puckboard.viz.recording`; ``puckboard.viz.hooks.attach`` wires the tools to a run.
"""
