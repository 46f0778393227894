"""``yade.params``: parameter namespaces of a script (``yade.params.table``)."""
