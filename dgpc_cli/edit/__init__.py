"""``dgpc edit``: the design session (``session``), its solver thread (``live``), the replay of
recorded drags (``replay``), the fabrication preview (``fabrication``) and the page (viser:
``page``, ``colours``). It sits above ``stages`` and reuses it; ``stages`` never imports it."""
