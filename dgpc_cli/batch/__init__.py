"""``dgpc batch``: a project of many patches (TOML) as a graph of dgpc commands.

* :mod:`.project` reads and checks the project file;
* :mod:`.graph` turns it into tasks (one dgpc command each, with its inputs and outputs);
* :mod:`.cache` decides which tasks can be reused (sha256 of inputs and options);
* :mod:`.summary` writes ``batch.json`` and ``index.html``.

Nothing here imports Dask or runs a command: :mod:`dgpc_cli.stages.batch` schedules the tasks
on a Dask cluster, and the command line runs each task (:mod:`dgpc_cli.cli.batch_tasks`).
"""
