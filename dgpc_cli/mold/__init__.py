"""Molds for nets isometric to a surface of revolution (paper §4.2.2, Prop. 4.3, §6.2.3).

* :mod:`.profile` — the check (5), the intrinsic data d(u), l(u) and the meridian r(u), x(u),
  h(u) of the surface of revolution, with N segments per turn or Minding's λ;
* :mod:`.panels` — K×K panels, their isometry error against the mold patch, flat panels
  (K = −δ_uu w / w ≈ 0) and the mold pieces of the sector;
* :mod:`.dxf` — the meridian profile as a DXF polyline in mm with the axis drawn;
* :mod:`.extract` — ``dgpc extract-mold``'s computation: the check, the mold, its pieces and
  the panel-to-mold map of one or several nets, in the nets' unit.
"""
