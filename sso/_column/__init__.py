"""The 3D steering column: hardpoints, yoke phasing, spline teeth, excitation.

One job per module:

* :mod:`sso._column.geometry`: :class:`ColumnGeometry` (angles, bend planes, phases);
* :mod:`sso._column.chain_matrix`: the exact chain as one 2x2 matrix, vectorised;
* :mod:`sso._column.cancel`: :func:`can_cancel` and the closed-form optimal phasings;
* :mod:`sso._column.phasing`: the best yoke phasing (with the shaft optimiser);
* :mod:`sso._column.joint_centres`: joint centres moved within boxes;
* :mod:`sso._column.splines`: :func:`best_spline_teeth`, fitter's instructions;
* :mod:`sso._column.excitation`: SAE AE-7 figures and the exact model over rpm;
* :mod:`sso._column.scenarios`: one yoke phasing for many fixed columns (the NLP);
* :mod:`sso._column.positions`: :func:`optimise_positions` (tilt, telescope);
* :mod:`sso._column.tolerances`, :mod:`sso._column.robust_phasing`: tolerances in the
  objective (:class:`Tolerances`, :func:`optimise_robust`);
* :mod:`sso._column.band`: :func:`tolerance_band`;
* :mod:`sso._column.feel`: steering feel on-centre and at lock;
* :mod:`sso._column.steering_range`: speed and torque ratio, transmission error from
  lock to lock (exact extremes);
* :mod:`sso._column.design`: a column and its phasing, given either way;
* :mod:`sso._column.dispatch`: :func:`sso.optimise`, which sends each problem (a
  shaft series, a four-bar, a column) to its optimiser.

Conventions: ``docs/column.md``; robust phasing: ``docs/robust.md``.
"""
