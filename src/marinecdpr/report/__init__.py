"""Report: files, figures and the HTML page of every command's results.

Its modules, each importing only those listed above it:

- ``files``: writing files safely: atomic renames, staged output folders, CSV and JSON.
- ``figures``: every figure (matplotlib), decimated to its pixels.
- ``view3d``: the pages' 3D view of the robot on the ship (its geometry in S, the plotly figure).
- ``text``: the words of a report (error table, findings, base motion) and the HTML page.
- ``writers``: each command's files (plan, main job, workspace, operability), composed from the above.
- ``cleaning``: the cleaning job's files (clean.csv, the coverage map, summary.json, report.html).
"""
