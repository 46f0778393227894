"""``yade.params.table``: parameters declared by ``readParamsFromTable`` (filled at run time)."""
