"""A vehicle driveline (gearbox, propshafts, centre bearings, pinion) on the column's 3D chain.

Above ``column`` in the layer order: the joints, their planes and the exact chain
are :class:`sso._column.geometry.ColumnGeometry`'s; this part adds what a driveline
engineer signs off (fitter's measurements, tubes, critical speeds, excitations
against the makers' limits, secondary couples and bearing loads, the makers' rules
and the yoke phasing for them).
"""
