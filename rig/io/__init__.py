"""Records in and out: the Record, channel names and units, channel maps, CSV, RPC III, MDF and TDMS files, time
stamps and rates, atomic writes."""
