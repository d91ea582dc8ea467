// Load + hull + mass properties benchmarks (filled in by the geometry work).
