"""Figures of bifurc's datasets, each drawing into given Axes or a new figure, never choosing a
matplotlib backend: bifurcation diagrams (:mod:`.diagram`), continued branches and their
two-parameter curves (:mod:`.branch`), time histories (:mod:`.history`) and regime maps
(:mod:`.map`).  Nothing is imported here: matplotlib loads when a figure is drawn.
"""
