!> The text of `mpm1d --help`: usage and the namelist reference.
module mpm_cli_help
   use mpm_version, only: code_version
   use mpm_config, only: config_t, catalog_parameters, config_groups, group_help, new_config
   use mpm_scenes, only: scene_slot_t
   use mpm_registry, only: parameter_t, parameter_help, parameter_listing
   use mpm_sweep, only: sweep_config_t, sweep_parameters
   implicit none
   private
   public :: print_help, print_parameters

contains

   subroutine print_help(unit)
      integer, intent(in) :: unit
      type(config_t), target :: local
      type(scene_slot_t), allocatable, target :: slots(:)
      type(parameter_t), allocatable :: table(:), sweep_table(:)
      type(sweep_config_t), target :: settings
      integer :: i
      write (unit, '(a)') code_version//' - Material Point Method in one dimension', &
         '', &
         'usage:', &
         '  mpm1d                 run the built-in verification case (bar, 20 elements, 1 particle per', &
         '                        element, 10% of dx/c, USL, 2 periods) and write bar.h5', &
         '  mpm1d input.nml       run what the namelist file describes (-: read it from standard input)', &
         '  mpm1d input.nml group.name=value ...   the same with variables replaced, checked as in the file,', &
         '                        e.g. discretisation.elements=40 discretisation.scheme=musl sweep.elements=10,20', &
         '  --quiet               print nothing on standard output (warnings and errors still on standard error)', &
         '  --dry-run             check everything, run nothing: the number of cases and the absolute output path', &
         '  mpm1d --help          this text;  mpm1d --version  the code version', &
         '  mpm1d --list-parameters   the parameter registry, tab-separated (what /config/parameters holds)', &
         '', &
         'namelist groups (all optional; each variable with its default, what it means and what it allows):'
      local = new_config()
      call catalog_parameters(local, slots, table)
      do i = 1, size(config_groups)
         write (unit, '(a)') '  &'//trim(config_groups(i))//': '//group_help(trim(config_groups(i)))
         write (unit, '(a)', advance='no') parameter_help(table, trim(config_groups(i)))
      end do
      write (unit, '(a)') '  &sweep: every combination of the lists below (the last varies fastest); one HDF5 table '// &
         '(docs/user-guide.md, Sweeps)', '    lists, each named as the variable it varies (a list left out holds its base value;', &
         '    the former plural names in brackets are still accepted):'
      do i = 1, size(table)
         if (len_trim(table(i)%sweep_list) == 0) cycle
         if (len_trim(table(i)%sweep_alias) > 0) then
            write (unit, '(a)') '      '//trim(table(i)%sweep_list)//' = '//trim(table(i)%group)//'.'// &
               trim(table(i)%name)//' values  ('//trim(table(i)%sweep_alias)//')'
         else
            write (unit, '(a)') '      '//trim(table(i)%sweep_list)//' = '//trim(table(i)%group)//'.'// &
               trim(table(i)%name)//' values'
         end if
      end do
      call sweep_parameters(settings, sweep_table)
      write (unit, '(a)', advance='no') parameter_help(sweep_table, 'sweep')
      write (unit, '(a)') &
         '', &
         'sweeps: mpm1d sweep.nml [--shard I/N] [--threads N] [--resume];  mpm1d merge OUT.h5 SHARD.h5 ...', &
         '  SIGINT, SIGTERM or SIGHUP stop a sweep: it writes the cases it finished (the others not_run);', &
         '  --resume runs the cases left in that file (the same input) and writes it again', &
         'single runs: &output checkpoint_steps = N keeps the whole state every N steps (and when SIGINT, SIGTERM', &
         '  or SIGHUP stops the run) in OUTPUT.checkpoint; mpm1d run.nml --restart continues from it, to the file', &
         '  the uninterrupted run writes', &
         '', &
         'exit codes: 0 done; 1 a guard stopped the run (history so far written); 2 bad input; 3 output failed;', &
         '  a sweep or run interrupted by SIGINT, SIGTERM, SIGHUP (a sweep writes what it finished, a run', &
         '  without checkpoints nothing): 130, 143, 129.', &
         'Every problem in the input is reported with the variable and its allowed range; nothing is written then.'
   end subroutine print_help

   !> The whole registry (the run's variables, then the &sweep settings), tab-separated, one line each.
   subroutine print_parameters(unit)
      integer, intent(in) :: unit
      type(config_t), target :: local
      type(scene_slot_t), allocatable, target :: slots(:)
      type(sweep_config_t), target :: settings
      type(parameter_t), allocatable :: table(:), sweep_table(:)
      local = new_config()
      call catalog_parameters(local, slots, table)
      call sweep_parameters(settings, sweep_table)
      write (unit, '(a)') parameter_listing([table, sweep_table])
   end subroutine print_parameters
end module mpm_cli_help
