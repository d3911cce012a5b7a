!> The named-id families: the lookup in both directions on lists written by hand (blanks, ids from
!> another first, unknown names and ids), and every family's ids against the names its output files
!> and messages use (the statuses as /summary and /cases write them; the shapes, transfers, laws, schemes and
!> integrators and formulations are the namelist's words).
program test_names
   use mpm_names, only: name_id, id_name
   use mpm_shape, only: shape_id, shape_name, all_shapes, shape_linear, shape_ugimp, shape_cpgimp, shape_bspline2, &
                        shape_bspline3, shape_cpdi, transfer_id, transfer_name, all_transfers, transfer_flip, &
                        transfer_pic, transfer_blend, transfer_apic, transfer_xpic, transfer_fmpm, transfer_asflip, &
                        formulation_id, formulation_updated, formulation_total
   use mpm_material, only: law_id, law_name, law_hencky, law_linear, law_elastoplastic
   use mpm_stepper, only: scheme_id, scheme_usf, scheme_usl, scheme_musl
   use mpm_implicit, only: integrator_id, integrator_explicit, integrator_implicit, integrator_quasi_static
   use mpm_diagnostics, only: status_name, status_ok, status_non_finite, status_volume_ratio, status_left_grid, &
                              status_energy_growth, status_cell_crossing, status_setup_failed, status_newton, &
                              status_domain_stretched, status_not_run
   use mpm_testing, only: tester_t, tester
   implicit none
   type(tester_t) :: t
   t = tester('test_names')
   if (t%case('lookup')) call lookup()
   if (t%case('families')) call families()
   call t%finish()

contains

   subroutine lookup()
      character(len=*), parameter :: list = 'alpha, beta,gamma ,  delta'
      call t%check('first name', name_id('alpha', list) == 1)
      call t%check('name after ", "', name_id('beta', list) == 2)
      call t%check('name after "," with no blank', name_id('gamma', list) == 3)
      call t%check('name after two blanks, last', name_id('delta', list) == 4)
      call t%check('trailing blanks of the name ignored', name_id('beta    ', list) == 2)
      call t%check('a prefix is not a name', name_id('alph', list) == 0)
      call t%check('a longer word is not a name', name_id('alphabet', list) == 0)
      call t%check('an empty name is unknown', name_id('', list) == 0)
      call t%check('a leading blank is not ignored', name_id(' beta', list) == 0)
      call t%check('unknown name: first - 1', name_id('zeta', list, first=-1) == -2)
      call t%check('ids from first', name_id('alpha', list, first=-1) == -1 .and. name_id('delta', list, first=0) == 3)
      call t%check('id 1 -> alpha', id_name(1, list) == 'alpha')
      call t%check('id 3 -> gamma (the blank before the comma dropped)', len(id_name(3, list)) == 5 .and. &
                   id_name(3, list) == 'gamma')
      call t%check('id 4 -> delta', id_name(4, list) == 'delta')
      call t%check('ids from first: -1 -> alpha', id_name(-1, list, first=-1) == 'alpha')
      call t%check('id beyond the list -> unknown', id_name(5, list) == 'unknown')
      call t%check('id below first -> unknown', id_name(0, list) == 'unknown')
   end subroutine lookup

   subroutine families()
      integer :: k
      call pair('shape', shape_linear, 'linear', shape_id, shape_name)
      call pair('shape', shape_ugimp, 'ugimp', shape_id, shape_name)
      call pair('shape', shape_cpgimp, 'cpgimp', shape_id, shape_name)
      call pair('shape', shape_bspline2, 'bspline2', shape_id, shape_name)
      call pair('shape', shape_bspline3, 'bspline3', shape_id, shape_name)
      call pair('shape', shape_cpdi, 'cpdi', shape_id, shape_name)
      call pair('transfer', transfer_flip, 'flip', transfer_id, transfer_name)
      call pair('transfer', transfer_pic, 'pic', transfer_id, transfer_name)
      call pair('transfer', transfer_blend, 'blend', transfer_id, transfer_name)
      call pair('transfer', transfer_apic, 'apic', transfer_id, transfer_name)
      call pair('transfer', transfer_xpic, 'xpic', transfer_id, transfer_name)
      call pair('transfer', transfer_fmpm, 'fmpm', transfer_id, transfer_name)
      call pair('transfer', transfer_asflip, 'asflip', transfer_id, transfer_name)
      call t%check('formulation updated', formulation_id('updated') == formulation_updated)
      call t%check('formulation total', formulation_id('total') == formulation_total)
      call pair('law', law_hencky, 'hencky', law_id, law_name)
      call pair('law', law_linear, 'linear', law_id, law_name)
      call pair('law', law_elastoplastic, 'elastoplastic', law_id, law_name)
      do k = 1, size(all_shapes)
         call t%check('all_shapes('//char(48 + k)//') round trip', shape_id(shape_name(all_shapes(k))) == all_shapes(k))
      end do
      do k = 1, size(all_transfers)
         call t%check('all_transfers('//char(48 + k)//') round trip', &
                      transfer_id(transfer_name(all_transfers(k))) == all_transfers(k))
      end do
      call t%check('unknown shape: 0', shape_id('hat') == 0)
      call t%check('scheme usf', scheme_id('usf') == scheme_usf)
      call t%check('scheme usl', scheme_id('usl') == scheme_usl)
      call t%check('scheme musl', scheme_id('musl') == scheme_musl)
      call t%check('unknown scheme: 0', scheme_id('uslx') == 0)
      call t%check('integrator explicit', integrator_id('explicit') == integrator_explicit)
      call t%check('integrator implicit', integrator_id('implicit') == integrator_implicit)
      call t%check('integrator quasi_static', integrator_id('quasi_static') == integrator_quasi_static)
      call t%check('unknown integrator: explicit', integrator_id('newmark') == integrator_explicit)
      ! the statuses' codes and names as output files carry them (status, status_name)
      call t%check('status ok = 0', status_ok == 0 .and. status_name(status_ok) == 'ok')
      call t%check('status non_finite = 1', status_non_finite == 1 .and. status_name(1) == 'non_finite')
      call t%check('status volume_ratio_not_positive = 2', status_volume_ratio == 2 .and. &
                   status_name(2) == 'volume_ratio_not_positive')
      call t%check('status left_grid = 3', status_left_grid == 3 .and. status_name(3) == 'left_grid')
      call t%check('status energy_growth = 4', status_energy_growth == 4 .and. status_name(4) == 'energy_growth')
      call t%check('status cell_crossing = 5', status_cell_crossing == 5 .and. status_name(5) == 'cell_crossing')
      call t%check('status setup_failed = 6', status_setup_failed == 6 .and. status_name(6) == 'setup_failed')
      call t%check('status newton_not_converged = 7', status_newton == 7 .and. status_name(7) == 'newton_not_converged')
      call t%check('status not_run = -1', status_not_run == -1 .and. status_name(-1) == 'not_run')
      call t%check('status domain_stretched = 8', status_domain_stretched == 8 .and. &
                   status_name(8) == 'domain_stretched')
      call t%check('an unknown status code', status_name(9) == 'unknown' .and. status_name(-2) == 'unknown')
   end subroutine families

   subroutine pair(family, id, name, to_id, to_name)
      character(len=*), intent(in) :: family, name
      integer, intent(in) :: id
      interface
         pure integer function to_id(name)
            character(len=*), intent(in) :: name
         end function to_id
         pure function to_name(id) result(name)
            integer, intent(in) :: id
            character(len=:), allocatable :: name
         end function to_name
      end interface
      call t%check(family//' '//name//' -> its id', to_id(name) == id)
      call t%check(family//' id of '//name//' -> '//name, to_name(id) == name)
   end subroutine pair
end program test_names
