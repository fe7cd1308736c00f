"""The 3D steering column: hardpoints, yoke phasing, spline teeth, excitation.

One job per module:

* :mod:`sso.column.geometry`: :class:`ColumnGeometry` (angles, bend planes, phases);
* :mod:`sso.column.chain_matrix`: the exact chain as one 2x2 matrix, vectorised;
* :mod:`sso.column.cancel`: :func:`can_cancel` and the closed-form optimal phasings;
* :mod:`sso.column.phasing`: :func:`optimise_phasing` with :func:`sso.optimise`;
* :mod:`sso.column.splines`: :func:`best_spline_teeth`, fitter's instructions;
* :mod:`sso.column.excitation`: SAE AE-7 figures and the exact model over rpm.

Conventions: ``docs/column.md``.
"""
