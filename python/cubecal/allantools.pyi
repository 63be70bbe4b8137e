# Type stub of cubecal/allantools.py: AllanTools' module allantools.allantools.
from ._allantools import (adev as adev, calc_adev_phase as calc_adev_phase, calc_gcodev_phase as calc_gcodev_phase,
                          calc_hdev_phase as calc_hdev_phase, calc_htotdev_freq as calc_htotdev_freq,
                          calc_mtotdev_phase as calc_mtotdev_phase, calc_pdev_phase as calc_pdev_phase,
                          gcodev as gcodev, gradev as gradev, hdev as hdev, htotdev as htotdev, mdev as mdev,
                          mtie as mtie, mtie_phase_fast as mtie_phase_fast, mtotdev as mtotdev, oadev as oadev,
                          ohdev as ohdev, pdev as pdev, tdev as tdev, theo1 as theo1,
                          three_cornered_hat_phase as three_cornered_hat_phase, tierms as tierms, totdev as totdev,
                          ttotdev as ttotdev)
from ._conversions import (frequency2fractional as frequency2fractional, frequency2phase as frequency2phase,
                           input_to_phase as input_to_phase, mtie_rolling_window as mtie_rolling_window,
                           phase2frequency as phase2frequency, phase2radians as phase2radians,
                           remove_small_ns as remove_small_ns, tau_generator as tau_generator,
                           tau_reduction as tau_reduction, trim_data as trim_data)
from ._psd import (adev2psd_piecewise_approx as adev2psd_piecewise_approx, psd2allan as psd2allan,
                   psd_piecewise_to_adev as psd_piecewise_to_adev)

from . import ci as ci

__version__: str
