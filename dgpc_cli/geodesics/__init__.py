"""Curves on triangle meshes for ``dgpc init`` (SPEC §5): plane sections, geodesics traced
orthogonally from a base curve (smooth geodesic parallel coordinates, paper Def. 2.1), and the
largest grid rectangle that stays on the mesh; and the laths of a geodesic gridshell, two nets'
geodesics with their crossings (:mod:`.laths`)."""
