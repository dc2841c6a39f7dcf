"""Build of the verification report and the reproducible paper (``make report``)."""
