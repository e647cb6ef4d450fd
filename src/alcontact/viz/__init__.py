"""Matplotlib figures of contact solutions (matplotlib is imported when a figure is made).

- :mod:`alcontact.viz.plots` -- contact pressure profile against the analytical one,
  convergence history of the outer iterations, convergence per load step, load-displacement curve
- :mod:`alcontact.viz.pictures` -- pictures of the deformed body coloured by contact pressure and
  by von Mises stress
"""

from __future__ import annotations

from .plots import (
    Units,
    contact_center,
    contact_coordinate,
    contact_half_width,
    edge_search_applies,
    loaded_half_width,
    convergence_figure,
    force_path_figure,
    load_displacement_figure,
    load_path_phases,
    pressure_figure,
    save_convergence_plot,
    save_figure,
    save_pressure_plot,
    steps_figure,
)
from .pictures import body_figure, save_body_pictures

__all__ = [
    "Units",
    "contact_coordinate",
    "contact_center",
    "contact_half_width",
    "edge_search_applies",
    "loaded_half_width",
    "pressure_figure",
    "convergence_figure",
    "save_figure",
    "save_pressure_plot",
    "save_convergence_plot",
    "steps_figure",
    "load_displacement_figure",
    "body_figure",
    "save_body_pictures",
    "load_path_phases",
    "force_path_figure",
]
