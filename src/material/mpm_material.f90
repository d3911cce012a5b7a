!> The material layer: the law a body follows (`&material law=`), where each law lives, and what the
!> rest of the code asks of a law: the stress update of a step, the tangent modulus d sigma/d eps,
!> the stored and dissipated energy, and the per-particle state it needs.
!>   hencky         sigma = E ln J, integrated in rate form sigma += E d eps (mpm_material_elastic)
!>   linear         sigma = E (J - 1) (mpm_material_elastic)
!>   elastoplastic  Hencky elasticity with linear isotropic hardening, radial return on the hencky trial
!>                  update (Simo and Hughes 1998; mpm_material_plastic)
!> Only the elastoplastic law carries state of its own (plastic strain and hardening variable per
!> particle, allocated by material_state); hencky and linear runs carry, compute and write nothing new.
!> The per-particle kernels are elemental (elastic_update, linear_update, radial_return), so that a
!> fused stress pass can call the law of one particle; the whole-array updates here serve the generic path.
module mpm_material
   use mpm_kinds, only: dp
   use mpm_names, only: name_id, id_name
   use mpm_errors, only: error_t, set_error
   use mpm_strings, only: str
   use mpm_particles, only: particles_t
   use mpm_material_elastic, only: elastic_update_all, elastic_update_each, strain_energy_density, &
                                   linear_update_all, linear_update_each, linear_energy_density
   use mpm_material_plastic, only: plastic_update_all, plastic_tangent, plastic_work_density, dissipation_density, &
                                   radial_return
   implicit none
   private
   public :: material_t, law_hencky, law_linear, law_elastoplastic, known_laws, law_id, law_name
   public :: update_material, stored_energy, plastic_work, dissipated_energy, material_state, law_tangent
   public :: material_report
   public :: law_stress, law_stiffness, law_stress_stiffness, update_material_finite, log_one_plus

   !> Law ids.
   integer, parameter :: law_hencky = 1, law_linear = 2, law_elastoplastic = 3
   !> The laws' names, as `&material law=` takes them.
   character(len=*), parameter :: known_laws = 'hencky, linear, elastoplastic'

   !> A body's material: its law and parameters. Scenes of several materials give the parameters per
   !> particle instead (particles%youngs_modulus_of, yield_stress_of, hardening_modulus_of).
   type :: material_t
      integer :: law = law_hencky
      real(dp) :: youngs_modulus = 0.0_dp      !< E (Pa)
      real(dp) :: yield_stress = huge(1.0_dp)  !< sigma_y (Pa), elastoplastic only
      real(dp) :: hardening_modulus = 0.0_dp   !< H (Pa), elastoplastic only
   end type material_t

contains

   pure integer function law_id(name)
      character(len=*), intent(in) :: name
      law_id = name_id(name, known_laws)
   end function law_id

   pure function law_name(law) result(name)
      integer, intent(in) :: law
      character(len=:), allocatable :: name
      name = id_name(law, known_laws)
   end function law_name

   !> The per-particle state the law needs, in its initial value: for the elastoplastic law the plastic
   !> strain and hardening variable (zero), and, in scenes of several materials that did not set them,
   !> each particle's yield stress and hardening modulus from `material`. Nothing for the elastic laws.
   subroutine material_state(material, particles, error)
      type(material_t), intent(in) :: material
      type(particles_t), intent(inout) :: particles
      type(error_t), allocatable, intent(out) :: error
      integer :: stat
      if (material%law /= law_elastoplastic) return
      allocate (particles%plastic_strain(particles%count), particles%hardening(particles%count), source=0.0_dp, &
                stat=stat)
      if (stat == 0 .and. allocated(particles%youngs_modulus_of) .and. .not. allocated(particles%yield_stress_of)) &
         allocate (particles%yield_stress_of(particles%count), source=material%yield_stress, stat=stat)
      if (stat == 0 .and. allocated(particles%youngs_modulus_of) .and. &
          .not. allocated(particles%hardening_modulus_of)) &
         allocate (particles%hardening_modulus_of(particles%count), source=material%hardening_modulus, stat=stat)
      if (stat /= 0) call set_error(error, "cannot allocate the plastic state of "//str(particles%count)// &
                                    " particles (out of memory)")
   end subroutine material_state

   !> The law's update of every particle by its strain increment `dstrain`: stress, J and the law's state;
   !> `energy` = the stored energy after the update, `smallest` = the smallest J, `work` = the plastic
   !> work (0 for the elastic laws). Young's modulus per particle where the scene gave one.
   subroutine update_material(material, dstrain, particles, energy, smallest, work)
      type(material_t), intent(in) :: material
      real(dp), intent(in), contiguous :: dstrain(:)
      type(particles_t), intent(inout) :: particles
      real(dp), intent(out) :: energy, smallest, work
      work = 0.0_dp
      associate (p => particles)
         select case (material%law)
         case (law_linear)
            if (allocated(p%youngs_modulus_of)) then
               call linear_update_each(p%youngs_modulus_of, dstrain, p%volume0_of, p%stress, p%volume_ratio, energy, &
                                       smallest)
            else
               call linear_update_all(material%youngs_modulus, dstrain, p%volume0_of, p%stress, p%volume_ratio, &
                                      energy, smallest)
            end if
         case (law_elastoplastic)
            if (allocated(p%youngs_modulus_of)) then
               call plastic_update_all(p%youngs_modulus_of, p%yield_stress_of, p%hardening_modulus_of, dstrain, &
                                       p%volume0_of, p%stress, p%volume_ratio, p%plastic_strain, p%hardening, energy, &
                                       smallest, work)
            else
               call plastic_update_all([material%youngs_modulus], [material%yield_stress], &
                                       [material%hardening_modulus], dstrain, p%volume0_of, p%stress, p%volume_ratio, &
                                       p%plastic_strain, p%hardening, energy, smallest, work)
            end if
         case default ! hencky (several materials: one test per step, none per particle)
            if (allocated(p%youngs_modulus_of)) then
               call elastic_update_each(p%youngs_modulus_of, dstrain, p%volume0_of, p%stress, p%volume_ratio, energy, &
                                        smallest)
            else
               call elastic_update_all(material%youngs_modulus, dstrain, p%volume0_of, p%stress, p%volume_ratio, &
                                       energy, smallest)
            end if
         end select
      end associate
   end subroutine update_material

   !> The stored (elastic) energy of the particles as they are: sigma^2 V/(2E) (hencky, elastoplastic),
   !> sigma^2 V0/(2E) (linear: its exact stored energy). Needs per-particle volumes (generic path).
   real(dp) function stored_energy(material, particles) result(energy)
      type(material_t), intent(in) :: material
      type(particles_t), intent(in) :: particles
      associate (p => particles)
         if (material%law == law_linear) then
            if (allocated(p%youngs_modulus_of)) then
               energy = sum(linear_energy_density(p%youngs_modulus_of, p%stress, p%volume0_of))
            else
               energy = sum(linear_energy_density(material%youngs_modulus, p%stress, p%volume0_of))
            end if
         else if (allocated(p%youngs_modulus_of)) then
            energy = sum(strain_energy_density(p%youngs_modulus_of, p%stress, p%volume_ratio*p%volume0_of))
         else
            energy = sum(strain_energy_density(material%youngs_modulus, p%stress, p%volume_ratio*p%volume0_of))
         end if
      end associate
   end function stored_energy

   !> The plastic work done on the particles so far, sum (sigma_y alpha + H alpha^2/2) V0 (0 unless
   !> the law is elastoplastic). V0 per particle where the particles carry it (the generic path, and the
   !> scenes of several materials, which give the yield stresses per particle), else the particles' one V0
   !> (the fused kernels' bar; no array of it is formed, which would add 8 bytes per particle of peak memory).
   real(dp) function plastic_work(material, particles) result(work)
      type(material_t), intent(in) :: material
      type(particles_t), intent(in) :: particles
      work = 0.0_dp
      if (material%law /= law_elastoplastic .or. .not. allocated(particles%hardening)) return
      if (allocated(particles%yield_stress_of)) then
         work = sum(plastic_work_density(particles%yield_stress_of, particles%hardening_modulus_of, &
                                         particles%hardening, particles%volume0_of))
      else if (allocated(particles%volume0_of)) then
         work = sum(plastic_work_density(material%yield_stress, material%hardening_modulus, particles%hardening, &
                                         particles%volume0_of))
      else
         work = sum(plastic_work_density(material%yield_stress, material%hardening_modulus, particles%hardening, &
                                         particles%volume0))
      end if
   end function plastic_work

   !> The energy dissipated so far, sum sigma_y alpha V0 (the plastic work less what the hardening stores).
   real(dp) function dissipated_energy(material, particles) result(energy)
      type(material_t), intent(in) :: material
      type(particles_t), intent(in) :: particles
      energy = 0.0_dp
      if (material%law /= law_elastoplastic .or. .not. allocated(particles%hardening)) return
      if (allocated(particles%yield_stress_of)) then
         energy = sum(dissipation_density(particles%yield_stress_of, particles%hardening, particles%volume0_of))
      else if (allocated(particles%volume0_of)) then
         energy = sum(dissipation_density(material%yield_stress, particles%hardening, particles%volume0_of))
      else
         energy = sum(dissipation_density(material%yield_stress, particles%hardening, particles%volume0))
      end if
   end function dissipated_energy

   !> The tangent modulus d sigma_{n+1}/d (d eps) of a step of `law` from the state before it (stress,
   !> J, hardening variable) by the increment `dstrain`: hencky E; linear E J (sigma = E (J (1 + d eps) - 1));
   !> elastoplastic the consistent tangent, E or E H/(E + H) (mpm_material_plastic).
   elemental real(dp) function law_tangent(law, youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                           volume_ratio, hardening) result(tangent)
      integer, intent(in) :: law
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, volume_ratio, hardening
      select case (law)
      case (law_linear)
         tangent = youngs_modulus*volume_ratio
      case (law_elastoplastic)
         tangent = plastic_tangent(youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, hardening)
      case default
         tangent = youngs_modulus
      end select
   end function law_tangent

   !> The finite strain increments of the implicit integrators (mpm_implicit), whose steps are far longer
   !> than the explicit ones. A step moves a particle's neighbourhood by d eps = F_step - 1 (J_{n+1} =
   !> J_n (1 + d eps) exactly), and the law is integrated exactly over it: hencky (and the elastic part of
   !> elastoplastic) by the logarithmic increment ln(1 + d eps), so that sigma = E ln J at any step size
   !> (the explicit update sigma += E d eps is its first-order form: d eps^2/2 apart per step, nothing at
   !> the explicit step, first order in dt at implicit ones); linear as sigma_n + E J_n d eps, which is
   !> E (J_{n+1} - 1) written as an increment, so that its round-off is eps |sigma| and not the E eps of
   !> J - 1 formed from a J stored near 1 (which stops a tight Newton tolerance at small strain).
   !> law_stress is the stress a step reaches from the state before it, without changing the state (the
   !> residual of a Newton iteration), law_stiffness its derivative d sigma_{n+1}/d (d eps) (the tangent:
   !> law_tangent of the logarithmic increment times d ln(1 + d eps)/d (d eps) = 1/(1 + d eps)).
   elemental real(dp) function law_stress(law, youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                          volume_ratio, hardening) result(updated)
      integer, intent(in) :: law
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, volume_ratio, hardening
      real(dp) :: plastic_strain, alpha
      select case (law)
      case (law_linear)
         updated = linear_stress(youngs_modulus, dstrain, stress, volume_ratio)
      case (law_elastoplastic)
         updated = stress
         plastic_strain = 0.0_dp
         alpha = hardening
         call radial_return(youngs_modulus, yield_stress, hardening_modulus, log_one_plus(dstrain), updated, &
                            plastic_strain, alpha)
      case default
         updated = hencky_stress(youngs_modulus, dstrain, stress)
      end select
   end function law_stress

   !> law_stress of the linear law, sigma_n + E J_n d eps.
   elemental real(dp) function linear_stress(youngs_modulus, dstrain, stress, volume_ratio) result(updated)
      real(dp), intent(in) :: youngs_modulus, dstrain, stress, volume_ratio
      updated = stress + youngs_modulus*volume_ratio*dstrain
   end function linear_stress

   !> law_stress of hencky's law, sigma_n + E ln(1 + d eps).
   elemental real(dp) function hencky_stress(youngs_modulus, dstrain, stress) result(updated)
      real(dp), intent(in) :: youngs_modulus, dstrain, stress
      updated = stress + youngs_modulus*log_one_plus(dstrain)
   end function hencky_stress

   !> d law_stress/d (d eps) (see law_stress).
   elemental real(dp) function law_stiffness(law, youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                             volume_ratio, hardening) result(stiffness)
      integer, intent(in) :: law
      real(dp), intent(in) :: youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, volume_ratio, hardening
      if (law == law_linear) then
         stiffness = law_tangent(law, youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, volume_ratio, &
                                 hardening)
      else
         stiffness = law_tangent(law, youngs_modulus, yield_stress, hardening_modulus, log_one_plus(dstrain), stress, &
                                 volume_ratio, hardening)/(1.0_dp + dstrain)
      end if
   end function law_stiffness

   !> law_stress and law_stiffness of particles 1..count, the elastic laws each in a loop of its own with
   !> their expressions inlined (law_stress and law_stiffness called element by element from another
   !> module cost four times the arithmetic; gfortran does not inline them): the same values, bit for bit.
   pure subroutine law_stress_stiffness(law, count, youngs_modulus, yield_stress, hardening_modulus, dstrain, stress, &
                                        volume_ratio, hardening, updated, stiffness)
      integer, intent(in) :: law, count
      real(dp), intent(in) :: youngs_modulus(count), yield_stress(count), hardening_modulus(count), dstrain(count), &
                              stress(count), volume_ratio(count), hardening(count)
      real(dp), intent(out) :: updated(count), stiffness(count)
      real(dp) :: u, logarithm
      integer :: p
      select case (law)
      case (law_linear) ! (law_tangent's E J_n: the increment's derivative)
         do p = 1, count
            updated(p) = linear_stress(youngs_modulus(p), dstrain(p), stress(p), volume_ratio(p))
            stiffness(p) = youngs_modulus(p)*volume_ratio(p)
         end do
      case (law_hencky) ! (law_tangent's E times d ln(1 + d eps)/d (d eps))
         do p = 1, count
            ! (hencky_stress with log_one_plus written out: as a call, a third of this loop's instructions)
            u = 1.0_dp + dstrain(p)
            if (u == 1.0_dp) then
               logarithm = dstrain(p)
            else
               logarithm = log(u)*dstrain(p)/(u - 1.0_dp)
            end if
            updated(p) = stress(p) + youngs_modulus(p)*logarithm
            stiffness(p) = youngs_modulus(p)/u
         end do
      case default
         do p = 1, count
            updated(p) = law_stress(law, youngs_modulus(p), yield_stress(p), hardening_modulus(p), dstrain(p), &
                                    stress(p), volume_ratio(p), hardening(p))
            stiffness(p) = law_stiffness(law, youngs_modulus(p), yield_stress(p), hardening_modulus(p), dstrain(p), &
                                         stress(p), volume_ratio(p), hardening(p))
         end do
      end select
   end subroutine law_stress_stiffness

   !> The state update of a finite increment (see law_stress): the law's own update (update_material) by
   !> the logarithmic increment for hencky and elastoplastic, then J_{n+1} = J_n (1 + d eps) and the stored
   !> energy and smallest J of that J; the linear law's update as it is (its stress is E (J - 1)).
   !> `stress`, when given: law_stress's stresses at these increments, formed already (the implicit
   !> integrator's last residual); hencky's update is exactly that stress, sigma_n + E ln(1 + d eps), and
   !> takes it instead of forming the logarithms again.
   subroutine update_material_finite(material, dstrain, particles, energy, smallest, work, stress)
      type(material_t), intent(in) :: material
      real(dp), intent(in), contiguous :: dstrain(:)
      type(particles_t), intent(inout) :: particles
      real(dp), intent(out) :: energy, smallest, work
      real(dp), intent(in), contiguous, optional :: stress(:)
      real(dp), allocatable :: volume_ratio(:)
      if (material%law == law_linear) then
         call update_material(material, dstrain, particles, energy, smallest, work)
         return
      end if
      volume_ratio = particles%volume_ratio*(1.0_dp + dstrain)
      if (material%law == law_hencky .and. present(stress)) then
         particles%stress = stress
         work = 0.0_dp
      else
         call update_material(material, log_one_plus(dstrain), particles, energy, smallest, work)
      end if
      particles%volume_ratio = volume_ratio
      energy = stored_energy(material, particles)
      smallest = minval(volume_ratio)
   end subroutine update_material_finite

   !> ln(1 + x) to a few ulps also for |x| near eps (where log(1 + x) loses the digits of x): Goldberg,
   !> "What every computer scientist should know about floating-point arithmetic", ACM Computing Surveys
   !> 23(1), 1991, doi:10.1145/103162.103163, theorem 4.
   elemental real(dp) function log_one_plus(x) result(y)
      real(dp), intent(in) :: x
      real(dp) :: u
      u = 1.0_dp + x
      if (u == 1.0_dp) then
         y = x
      else
         y = log(u)*x/(u - 1.0_dp)
      end if
   end function log_one_plus

   !> What the law adds to a run's /summary (the elastoplastic law only): the plastic work, the energy
   !> dissipated and the energy stored in the hardening (J per unit area), the largest plastic strain
   !> and hardening variable, and the fraction of the particles that yielded.
   subroutine material_report(material, particles, names, values)
      type(material_t), intent(in) :: material
      type(particles_t), intent(in) :: particles
      character(len=32), allocatable, intent(out) :: names(:)
      real(dp), allocatable, intent(out) :: values(:)
      real(dp) :: work, dissipated
      if (material%law /= law_elastoplastic .or. .not. allocated(particles%hardening)) then
         allocate (names(0), values(0))
         return
      end if
      work = plastic_work(material, particles)
      dissipated = dissipated_energy(material, particles)
      names = [character(len=32) :: 'plastic_work', 'dissipated_energy', 'hardening_energy', 'max_plastic_strain', &
               'max_hardening', 'yielded_fraction']
      values = [work, dissipated, work - dissipated, max(maxval(abs(particles%plastic_strain)), 0.0_dp), &
                max(maxval(particles%hardening), 0.0_dp), &
                real(count(particles%hardening > 0.0_dp), dp)/max(particles%count, 1)]
   end subroutine material_report
end module mpm_material
