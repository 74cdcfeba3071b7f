"""Schemathesis against /openapi.json: no server error, no response that violates the schema.

Bounded (a fixed number of examples per operation, no shrinking) so CI stays fast.
"""
import schemathesis
from hypothesis import HealthCheck, Phase, settings
from schemathesis.checks import not_a_server_error
from schemathesis.specs.openapi.checks import response_schema_conformance

from service.app import app

schema = schemathesis.openapi.from_asgi("/openapi.json", app)


@schema.parametrize()
@settings(max_examples=25, deadline=None, phases=[Phase.explicit, Phase.generate],
          suppress_health_check=list(HealthCheck))
def test_openapi_contract(case):
    case.call_and_validate(checks=[not_a_server_error, response_schema_conformance])
