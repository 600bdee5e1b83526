"""Report: files, figures and the HTML page of every command's results."""
