#!/bin/bash
# Old and new checkouts alternated, one fresh process each, the same census (one.py: values x starts, 1 worker):
#   git archive addb4fe | tar -x -C /tmp/old
#   benchmarks/reports/attractors-lorenz84/interleave.sh /tmp/old . 100 4.7,5.0,5.5 2 out.txt
# Each line of out.txt: side, 1-minute load at its start, one.py's JSON (wall, CPU, fresh starts' CPU, samples per
# start, the census' lines).
OLD=$1; NEW=$2; N=$3; VALS=$4; ROUNDS=$5; OUT=$(realpath -m $6)
ONE=$(realpath $(dirname $0))/one.py
PY=${PYTHON:-/work/main/.venv/bin/python}
: > $OUT
for r in $(seq 1 $ROUNDS); do
  for side in old new; do
    if [ $side = old ]; then dir=$(realpath $OLD); else dir=$(realpath $NEW); fi
    load=$(cut -d' ' -f1 /proc/loadavg)
    (cd $dir && PYTHONPATH=$dir MPLBACKEND=Agg $PY $ONE $N $VALS | sed "s/^/$side $load /" >> $OUT)
  done
done
