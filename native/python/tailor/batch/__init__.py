"""``tailor batch``'s pieces, kept apart from the command's argument parsing
(``tailor.commands.batch``):

- ``tailor.batch.jobs``: the JOBS file (explicit jobs and generated ones), each job's input hash,
  its outputs written atomically and the done marker written last;
- ``tailor.batch.execute``: one job, run exactly as ``tailor simulate`` (and ``tailor import`` for
  a pattern) would run it, in a private folder; no Ray here;
- ``tailor.batch.runner``: the jobs on Ray (a cluster at an address, or a local instance), retries,
  progress and the JSON-lines log. Ray is imported there only, when a batch runs: it is no
  dependency of the ``tailor`` wheel that ships inside the Blender add-on.
"""
