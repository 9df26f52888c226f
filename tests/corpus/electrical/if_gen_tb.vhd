-- Family 12: if-generate choosing a source model; the generate bodies declare their own quantities.
-- ideal = false selects a 10 V step source with 1 kOhm internal resistance driving a 4 kOhm load with
-- c = 1 uF: k = 4/5, tau = (1 kOhm || 4 kOhm)*c = 0.8 ms,  vl(t) = 8*(1 - exp(-t/0.8 ms)).
-- (ideal = true would give vl = 10 V at once.)
library ieee;
use ieee.electrical_systems.all;

entity if_gen_tb is
  generic (ideal : boolean := false; u : voltage := 10.0; r_int : resistance := 1.0e3;
           r_load : resistance := 4.0e3; c : capacitance := 1.0e-6);
end entity if_gen_tb;

architecture behav of if_gen_tb is
  terminal load : electrical;
  quantity vl across il through load to electrical_ref;
  quantity vcap across icap through load to electrical_ref;
begin
  vl == r_load * il;
  icap == c * vcap'dot;

  ideal_source : if ideal generate
    quantity vs across isrc through load to electrical_ref;
  begin
    if domain = quiescent_domain use
      vs == 0.0;
    else
      vs == u;
    end use;
  end generate ideal_source;

  real_source : if not ideal generate
    terminal inner : electrical;
    quantity vs across isrc through inner to electrical_ref;
    quantity vri across iri through inner to load;
  begin
    if domain = quiescent_domain use
      vs == 0.0;
    else
      vs == u;
    end use;
    vri == r_int * iri;
  end generate real_source;
end architecture behav;
