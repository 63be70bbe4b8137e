"""cubecal as AllanTools' module allantools.allantools: the deviations,
their per-factor kernels, the conversions and the tau bookkeeping under the
names AllanTools gives them, so that `import allantools.allantools as at`
and `allantools.allantools.oadev(...)` keep working when allantools is
cubecal. Every name here is also cubecal's own (cubecal.oadev is
cubecal.allantools.oadev)."""
from ._cubecal import __version__
from ._allantools import (adev, calc_adev_phase, calc_gcodev_phase, calc_hdev_phase, calc_htotdev_freq,
                          calc_mtotdev_phase, calc_pdev_phase, gcodev, gradev, hdev, htotdev, mdev, mtie,
                          mtie_phase_fast, mtotdev, oadev, ohdev, pdev, tdev, theo1, three_cornered_hat_phase, tierms,
                          totdev, ttotdev)
from ._conversions import (frequency2fractional, frequency2phase, input_to_phase, mtie_rolling_window,
                           phase2frequency, phase2radians, remove_small_ns, tau_generator, tau_reduction, trim_data)
from ._psd import adev2psd_piecewise_approx, psd2allan, psd_piecewise_to_adev
from . import ci  # noqa: F401  (AllanTools' allantools.allantools.ci: its EDFs and intervals)

__all__ = ["__version__", "adev", "oadev", "mdev", "pdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev",
           "htotdev", "theo1", "mtie", "mtie_phase_fast", "tierms", "gradev", "gcodev", "calc_adev_phase",
           "calc_hdev_phase", "calc_pdev_phase", "calc_gcodev_phase", "calc_mtotdev_phase", "calc_htotdev_freq",
           "three_cornered_hat_phase", "frequency2phase", "phase2frequency", "phase2radians", "frequency2fractional",
           "input_to_phase", "trim_data", "tau_generator", "tau_reduction", "remove_small_ns", "mtie_rolling_window",
           "psd2allan", "adev2psd_piecewise_approx", "psd_piecewise_to_adev"]
