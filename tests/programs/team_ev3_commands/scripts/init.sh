#!/bin/bash
# Prepares the run: a log folder, and a busy minute of the robot's CPU (here a loop) before the start.
mkdir -p ./team_ev3_commands/logs
n=0
for i in $(seq 1 20000); do n=$(( (n + i * 7) % 1000003 )); done
echo "init: checksum $n" > ./team_ev3_commands/logs/init.txt
echo "init done"
