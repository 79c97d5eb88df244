#!/usr/bin/env bash
# A stand-in for a cluster's submit command: run the job script in the background, print its "job id".
nohup bash "$1" > "$1.out" 2>&1 &
echo $!
