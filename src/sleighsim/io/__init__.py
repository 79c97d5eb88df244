"""Reading and writing results: netCDF datasets with CF conventions, atomic files, integrity."""
