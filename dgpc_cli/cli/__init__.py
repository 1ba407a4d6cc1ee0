"""The ``dgpc`` command line: thin click commands over the library (cf. rasterio's ``rio``)."""
