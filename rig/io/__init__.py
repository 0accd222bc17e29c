"""Records in and out: the Record, channel names and units, CSV and RPC III files, time stamps, atomic writes."""
