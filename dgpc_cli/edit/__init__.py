"""The page of ``dgpc edit`` (viser): the net, its handles as gizmos, the live figures."""
