!> The text of `mpm1d --help`: usage and the namelist reference.
module mpm_cli_help
   use mpm_version, only: code_version
   use mpm_config, only: config_t, config_parameters, config_groups, group_help
   use mpm_registry, only: parameter_t, parameter_help
   implicit none
   private
   public :: print_help

contains

   subroutine print_help(unit)
      integer, intent(in) :: unit
      type(config_t), target :: local
      type(parameter_t), allocatable :: table(:)
      integer :: i
      write (unit, '(a)') code_version//' - Material Point Method in one dimension', &
         '', &
         'usage:', &
         '  mpm1d                 run the built-in verification case (bar, 20 elements, 1 particle per', &
         '                        element, 10% of dx/c, USL, 2 periods) and write bar.h5', &
         '  mpm1d input.nml       run what the namelist file describes', &
         '  mpm1d --help          this text;  mpm1d --version  the code version', &
         '', &
         'namelist groups (all optional; each variable with its default, what it means and what it allows):'
      local = config_t()
      call config_parameters(local, table)
      do i = 1, size(config_groups)
         write (unit, '(a)') '  &'//trim(config_groups(i))//': '//group_help(trim(config_groups(i)))
         write (unit, '(a)', advance='no') parameter_help(table, trim(config_groups(i)))
      end do
      write (unit, '(a)') &
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
