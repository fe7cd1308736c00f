"""The 3D steering column: hardpoints, yoke phasing, spline teeth, excitation.

Public names (re-exported from :mod:`sso` by the package):
:class:`ColumnGeometry`, :func:`can_cancel`, :class:`CancelVerdict`,
:func:`optimise_phasing`, :class:`PhasingResult`, :func:`best_spline_teeth`,
:class:`SplineResult`, :func:`excitation_table`, :class:`ExcitationRow`.
"""
