#!/bin/bash
# The exact heavy elastica of the cantilever test (postprocess/elastica.py --check): the small-deflection limit
# (tip deflection w L^4 / (8 B), clamp moment w L^2 / 2, within 0.1%), the integration converged in its step
# count (l*/c to 1e-8), and ASTM D1388's basis, c = l*/2 at 41.5 degrees within 0.1% (exact: c = 0.4999 l*).
set -eu
/usr/bin/python3 postprocess/elastica.py --check
