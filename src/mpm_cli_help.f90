!> The text of `mpm1d --help`: usage and the namelist reference.
module mpm_cli_help
   use mpm_version, only: code_version
   implicit none
   private
   public :: print_help

contains

   subroutine print_help(unit)
      integer, intent(in) :: unit
      write (unit, '(a)') code_version//' - Material Point Method in one dimension', &
         '', &
         'usage:', &
         '  mpm1d                 run the built-in verification case (bar, 20 elements, 1 particle per', &
         '                        element, 10% of dx/c, USL, 2 periods) and write bar.h5', &
         '  mpm1d input.nml       run what the namelist file describes', &
         '  mpm1d --help          this text;  mpm1d --version  the code version', &
         '', &
         'namelist groups (all optional; defaults shown):', &
         "  &scene kind='vibrating_bar', length=25.0, youngs_modulus=200.0e9, density=7800.0,", &
         '         velocity_amplitude=0.1, mode=1 /', &
         '      length (m) > 0, youngs_modulus (Pa) > 0, density (kg/m^3) > 0, velocity_amplitude v0 (m/s)', &
         '      finite, mode n >= 1: v(x,0) = v0 sin(beta_n x), beta_n = (2n-1) pi / (2 length)', &
         "  &discretisation scheme='usl', elements=20, particles_per_element=1, dt_fraction=0.1 /", &
         "      scheme: 'usf', 'usl' or 'musl'; elements >= 1; particles_per_element >= 1;", &
         '      dt = dt_fraction * dx / c, c = sqrt(youngs_modulus/density), 0 < dt_fraction <= 10', &
         '      margin_cells=-1: empty grid cells beyond each free end (-1: expected motion + 2 cells; >= 0)', &
         "      kernels='auto': fused linear kernels where they apply; 'generic': the generic layered path", &
         '  &run periods=2.0 /      or  &run end_time=0.0395 /  (seconds; give one of the two)', &
         '      periods of the simulated mode, 2 pi / omega_n each; steps = smallest n with n dt >= end time', &
         "  &output file='bar.h5', history=.true., snapshot_times=0.0, 0.01 /", &
         '      history: write u_cm(t), exact u_cm(t) and energies at every step;', &
         '      snapshot_times (s): particle and grid state at these times (none by default)', &
         '  &guards energy_growth_limit=10.0, max_cell_move=1.0 /', &
         '      a run stops (exit 1, history kept) on NaN/Infinity, J <= 0, a particle leaving the grid,', &
         '      total energy above energy_growth_limit x initial, or a move of more than max_cell_move cells', &
         '  &sweep schemes=..., elements=..., particles_per_element=..., dt_fractions=..., youngs_moduli=...,', &
         '         densities=..., velocity_amplitudes=..., modes=..., min_time=0.02, threads=0,', &
         '         timing_threads=1, histories=.false., shard=1, shards=1 /', &
         '      every combination of the lists; one HDF5 table (see README.md)', &
         '', &
         'sweeps: mpm1d sweep.nml [--shard I/N] [--threads N];  mpm1d merge OUT.h5 SHARD.h5 ...', &
         '', &
         'exit codes: 0 done; 1 a guard stopped the run (history so far written); 2 bad input; 3 output failed.', &
         'Every problem in the input is reported with the variable and its allowed range; nothing is written then.'
   end subroutine print_help
end module mpm_cli_help
